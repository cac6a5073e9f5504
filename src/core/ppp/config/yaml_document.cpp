#include "ppp_bayes_tree/ppp/config/yaml_document.h"

#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

#include <yaml-cpp/eventhandler.h>

namespace ppp {
namespace {

/// One mapping or sequence open in the document being scanned.
struct OpenCollection {
  bool mapping = false;
  std::string path;                      // its key path ("" for the document root)
  bool expecting_key = true;             // mapping: the next node is a key
  std::string key;                       // mapping: the key of the value that comes next
  std::size_t next_index = 0;            // sequence: the index of the next item
  std::map<std::string, YAML::Mark> key_marks;  // mapping: scalar key -> where it is written
};

std::string joinPath(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

/// The parser's events of one document: each mapping's scalar keys with their
/// lines; the second occurrence of a key throws ConfigError.
class DuplicateKeyScan : public YAML::EventHandler {
 public:
  explicit DuplicateKeyScan(std::string source_name) : source_name_(std::move(source_name)) {}

  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t) override { enter(mark, std::string("~")); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override { enter(mark, std::nullopt); }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t, const std::string& value) override {
    enter(mark, value);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {
    open(mark, false);
  }
  void OnSequenceEnd() override { stack_.pop_back(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    open(mark, true);
  }
  void OnMapEnd() override { stack_.pop_back(); }

 private:
  void open(const YAML::Mark& mark, bool mapping) {
    OpenCollection c;
    c.mapping = mapping;
    c.path = enter(mark, std::nullopt);
    stack_.push_back(std::move(c));
  }

  /// A node starts: its place in the enclosing collection (a key, a value or an
  /// item) is taken and its key path returned. `scalar_key`: its text when it is
  /// a scalar (only scalar keys are compared).
  std::string enter(const YAML::Mark& mark, const std::optional<std::string>& scalar_key) {
    if (stack_.empty()) return {};
    OpenCollection& top = stack_.back();
    if (!top.mapping) return top.path + "[" + std::to_string(top.next_index++) + "]";
    if (!top.expecting_key) {
      top.expecting_key = true;
      return joinPath(top.path, top.key);
    }
    top.expecting_key = false;
    top.key = scalar_key ? *scalar_key : std::string("<non-scalar key>");
    if (scalar_key) checkKey(top, mark);
    return joinPath(top.path, top.key);
  }

  void checkKey(OpenCollection& mapping, const YAML::Mark& mark) const {
    const auto [it, inserted] = mapping.key_marks.emplace(mapping.key, mark);
    if (inserted) return;
    const YAML::Mark& first = it->second;
    const std::string where =
        first.line == mark.line
            ? "at line " + std::to_string(mark.line + 1) + ", columns " + std::to_string(first.column + 1) + " and " +
                  std::to_string(mark.column + 1)
            : "at line " + std::to_string(first.line + 1) + " and line " + std::to_string(mark.line + 1);
    throw ConfigError(source_name_, joinPath(mapping.path, mapping.key),
                      "key given twice in one mapping, " + where +
                          " (only the first would be read: remove or merge one of them)");
  }

  std::string source_name_;
  std::vector<OpenCollection> stack_;
};

}  // namespace

void rejectDuplicateYamlKeys(const std::string& yaml_text, const std::string& source_name) {
  std::istringstream in(yaml_text);
  DuplicateKeyScan scan(source_name);
  try {
    YAML::Parser parser(in);
    parser.HandleNextDocument(scan);
  } catch (const YAML::Exception&) {  // syntax: reported by the loader, with its line
  }
}

YAML::Node parseYamlDocument(const std::string& yaml_text, const std::string& source_name) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(source_name, "", "YAML syntax error at line " + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  rejectDuplicateYamlKeys(yaml_text, source_name);
  return root;
}

YAML::Node loadYamlDocument(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path, "", "cannot open the file");
  std::ostringstream os;
  os << in.rdbuf();
  if (in.bad()) throw ConfigError(path, "", "read error");
  return parseYamlDocument(os.str(), path);
}

}  // namespace ppp
