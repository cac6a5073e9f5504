#pragma once
// YamlSection: strict reading of one YAML mapping of a configuration file.
// Every key must be known: a key that no get/section/raw call asked for is an
// error at finish(). A wrong type or an out-of-range value is an error naming
// the file, the key path ("stochastic.clock.initial_sigma_m") and the reason.
// Types are strict: a quoted scalar ("7", "true"; tag "!") is text, never a
// number or a bool; a bool is true or false (not YAML 1.1 yes/no/on/off); a
// list must be a sequence ([a] for one item, never a lone value).
// Absent keys keep their defaults. Used by PppConfig; the measurement-model and
// cycle-slip options bind their own sections with it.
#include <yaml-cpp/yaml.h>

#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace ppp {

class ConfigError : public std::runtime_error {
 public:
  ConfigError(const std::string& file, const std::string& key_path, const std::string& reason);
  const std::string& file() const { return file_; }
  const std::string& keyPath() const { return key_path_; }  // empty for file-level problems
  const std::string& reason() const { return reason_; }

 private:
  std::string file_, key_path_, reason_;
};

enum class Bound { Any, NonNegative, Positive };

class YamlSection {
 public:
  /// `node` must be a mapping, or null/undefined (an empty section); `path` is
  /// its key path in the file ("" for the document root).
  YamlSection(const YAML::Node& node, std::string file, std::string path);

  /// Finite number; `bound` restricts the sign. Integers are accepted.
  double number(const std::string& key, double fallback, Bound bound = Bound::Any);
  int integer(const std::string& key, int fallback, int minimum);
  bool boolean(const std::string& key, bool fallback);
  std::string text(const std::string& key, const std::string& fallback);
  /// One of `allowed` (error lists them).
  std::string choice(const std::string& key, const std::string& fallback, const std::set<std::string>& allowed);
  /// Sequence of single values (`[W, C]`; a lone value is an error: `[W]`).
  /// An empty sequence is an error unless `allow_empty`.
  std::vector<std::string> textList(const std::string& key, const std::vector<std::string>& fallback,
                                    bool allow_empty = false);
  /// Sequence of exactly `count` finite numbers (unquoted).
  std::vector<double> numberList(const std::string& key, const std::vector<double>& fallback, std::size_t count);
  /// Sub-mapping (empty when absent).
  YamlSection section(const std::string& key);
  /// The raw node of a key (bound later by someone else); must be a mapping or absent.
  YAML::Node rawMapping(const std::string& key);
  /// A key that moved elsewhere: throws ConfigError naming its new path when
  /// the key is given here (instead of "unknown key").
  void refuseMoved(const std::string& key, const std::string& new_path);
  /// Throws ConfigError for the first key of this mapping nobody asked for.
  void finish() const;

  bool has(const std::string& key) const { return node_.IsMap() && node_[key].IsDefined(); }
  /// The key is given as a single value (not a list or mapping).
  bool hasScalar(const std::string& key) const { return has(key) && node_[key].IsScalar(); }
  std::string keyPath(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  const std::string& file() const { return file_; }
  [[noreturn]] void fail(const std::string& key, const std::string& reason) const;

 private:
  YAML::Node scalar(const std::string& key);  // marks the key as known; throws unless a scalar
  YAML::Node node_;
  std::string file_, path_;
  std::set<std::string> known_;
};

}  // namespace ppp
