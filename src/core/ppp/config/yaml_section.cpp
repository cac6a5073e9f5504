#include "ppp_bayes_tree/ppp/config/yaml_section.h"

#include <cmath>
#include <sstream>

#include "ppp_bayes_tree/ppp/config/config_bounds.h"

namespace ppp {
namespace {
/// A scalar written in quotes (or a block scalar) in a file, or a string
/// parameter of ROS (xmlRpcToYaml tags them alike): text, never a number or a bool.
bool isQuotedText(const YAML::Node& n) { return n.IsScalar() && n.Tag() == "!"; }

/// What to write instead of quoted text where a number is expected.
std::string unquoteHint(const YAML::Node& n) {
  // rosparam reads YAML 1.1, where an exponent number needs a dot and a signed
  // exponent: 1e-4 and 3.0e6 are text there, 1.0e-4 and 3.0e+6 numbers.
  if (n.Scalar().find_first_of("eE") != std::string::npos)
    return ": write a plain number (without quotes; for rosparam (YAML 1.1) with a dot and a signed exponent, "
           "1.0e-4 or 3.0e+6)";
  return ": write a plain number (without quotes)";
}

/// A bound as written in the messages: 3600, 1e+08, 0.5.
std::string numberText(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

std::string describe(const YAML::Node& n) {
  if (isQuotedText(n)) return "the text \"" + n.Scalar() + "\" (quoted, or a string parameter)";
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsMap()) return "a mapping";
  if (n.IsSequence()) return "a sequence";
  return "nothing";
}
}  // namespace

ConfigError::ConfigError(const std::string& file, const std::string& key_path, const std::string& reason)
    : std::runtime_error(file + ": " + (key_path.empty() ? "" : key_path + ": ") + reason),
      file_(file),
      key_path_(key_path),
      reason_(reason) {}

YamlSection::YamlSection(const YAML::Node& node, std::string file, std::string path)
    : node_(node), file_(std::move(file)), path_(std::move(path)) {
  if (node_.IsDefined() && !node_.IsNull() && !node_.IsMap())
    throw ConfigError(file_, path_, "expected a mapping of keys, got " + describe(node_));
}

void YamlSection::fail(const std::string& key, const std::string& reason) const {
  throw ConfigError(file_, keyPath(key), reason);
}

YAML::Node YamlSection::scalar(const std::string& key) {
  known_.insert(key);
  if (!node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  YAML::Node n = node_[key];
  if (!n.IsDefined()) return n;
  if (!n.IsScalar()) fail(key, "expected a single value, got " + describe(n));
  return n;
}

double YamlSection::number(const std::string& key, double fallback, Bound bound) {
  const YAML::Node n = scalar(key);
  if (!n.IsDefined()) return fallback;
  if (isQuotedText(n)) fail(key, "expected a number, got " + describe(n) + unquoteHint(n));
  double v = 0.0;
  try {
    v = n.as<double>();
  } catch (const YAML::Exception&) {
    fail(key, "expected a number, got " + describe(n));
  }
  if (!std::isfinite(v)) fail(key, "expected a finite number, got " + describe(n));
  if (bound == Bound::NonNegative && v < 0.0) fail(key, "must be >= 0, got " + n.Scalar());
  if (bound == Bound::Positive && v <= 0.0) fail(key, "must be > 0, got " + n.Scalar());
  if (const auto lower = configLowerBound(keyPath(key)); lower && v < lower->min) {
    const auto upper = configUpperBound(keyPath(key));
    fail(key, "must be in [" + numberText(lower->min) + ", " + (upper ? numberText(upper->max) : std::string("inf")) +
                  "] (" + lower->reason + "), got " + n.Scalar());
  }
  if (const auto upper = configUpperBound(keyPath(key)); upper && v > upper->max) {
    const char* low = bound == Bound::Positive ? "(0, " : bound == Bound::NonNegative ? "[0, " : "(-inf, ";
    fail(key, "must be in " + std::string(low) + numberText(upper->max) + "] (" + upper->reason + "), got " +
                  n.Scalar());
  }
  return v;
}

int YamlSection::integer(const std::string& key, int fallback, int minimum) {
  const YAML::Node n = scalar(key);
  if (!n.IsDefined()) return fallback;
  if (isQuotedText(n)) fail(key, "expected an integer, got " + describe(n) + unquoteHint(n));
  int v = 0;
  try {
    v = n.as<int>();
  } catch (const YAML::Exception&) {
    fail(key, "expected an integer, got " + describe(n));
  }
  if (v < minimum) fail(key, "must be >= " + std::to_string(minimum) + ", got " + n.Scalar());
  if (const auto upper = configUpperBound(keyPath(key)); upper && v > upper->max)
    fail(key, "must be in [" + std::to_string(minimum) + ", " + numberText(upper->max) + "] (" + upper->reason +
                  "), got " + n.Scalar());
  return v;
}

bool YamlSection::boolean(const std::string& key, bool fallback) {
  const YAML::Node n = scalar(key);
  if (!n.IsDefined()) return fallback;
  // YAML 1.2 booleans only: yaml-cpp would also read yes/no/on/off/y/n (YAML 1.1),
  // and a quoted "true" is text.
  static const std::set<std::string> kTrue = {"true", "True", "TRUE"}, kFalse = {"false", "False", "FALSE"};
  if (!isQuotedText(n)) {
    if (kTrue.count(n.Scalar())) return true;
    if (kFalse.count(n.Scalar())) return false;
  }
  fail(key, "expected true or false, got " + describe(n));
}

std::string YamlSection::text(const std::string& key, const std::string& fallback) {
  const YAML::Node n = scalar(key);
  return n.IsDefined() ? n.Scalar() : fallback;
}

std::string YamlSection::choice(const std::string& key, const std::string& fallback,
                                const std::set<std::string>& allowed) {
  const std::string v = text(key, fallback);
  if (!allowed.count(v)) {
    std::ostringstream os;
    os << "expected one of";
    for (const auto& a : allowed) os << " " << a;
    os << ", got '" << v << "'";
    fail(key, os.str());
  }
  return v;
}

std::vector<std::string> YamlSection::textList(const std::string& key, const std::vector<std::string>& fallback,
                                               bool allow_empty) {
  known_.insert(key);
  if (!node_.IsMap()) return fallback;
  const YAML::Node n = node_[key];
  if (!n.IsDefined()) return fallback;
  std::vector<std::string> out;
  if (n.IsScalar()) {
    fail(key, "expected a list [a, b, ...], got the single value " + describe(n) + " (a list of one is [" +
                  n.Scalar() + "])");
  } else if (n.IsSequence()) {
    for (const auto& item : n) {
      if (!item.IsScalar()) fail(key, "expected a list of single values, got an item that is " + describe(item));
      out.push_back(item.Scalar());
    }
  } else {
    fail(key, "expected a list of values, got " + describe(n));
  }
  if (out.empty() && !allow_empty) fail(key, "must not be empty");
  return out;
}

std::vector<double> YamlSection::numberList(const std::string& key, const std::vector<double>& fallback,
                                            std::size_t count) {
  known_.insert(key);
  if (!node_.IsMap()) return fallback;
  const YAML::Node n = node_[key];
  if (!n.IsDefined()) return fallback;
  if (!n.IsSequence()) fail(key, "expected a list of " + std::to_string(count) + " numbers, got " + describe(n));
  std::vector<double> out;
  for (const auto& item : n) {
    double v = 0.0;
    bool ok = item.IsScalar() && !isQuotedText(item);
    if (ok) {
      try {
        v = item.as<double>();
      } catch (const YAML::Exception&) {
        ok = false;
      }
    }
    if (!ok || !std::isfinite(v)) fail(key, "expected finite numbers, got an item that is " + describe(item));
    out.push_back(v);
  }
  if (out.size() != count)
    fail(key, "expected a list of " + std::to_string(count) + " numbers, got " + std::to_string(out.size()));
  return out;
}

YamlSection YamlSection::section(const std::string& key) {
  known_.insert(key);
  YAML::Node n = node_.IsMap() ? node_[key] : YAML::Node(YAML::NodeType::Undefined);
  return YamlSection(n, file_, keyPath(key));
}

YAML::Node YamlSection::rawMapping(const std::string& key) {
  known_.insert(key);
  if (!node_.IsMap() || !node_[key].IsDefined() || node_[key].IsNull()) return YAML::Node(YAML::NodeType::Map);
  YAML::Node n = node_[key];
  if (!n.IsMap()) fail(key, "expected a mapping of keys, got " + describe(n));
  return YAML::Clone(n);
}

void YamlSection::refuseMoved(const std::string& key, const std::string& new_path) {
  known_.insert(key);
  if (has(key)) fail(key, "moved to " + new_path + ": write it there");
}

void YamlSection::finish() const {
  if (!node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "<non-scalar key>";
    if (!known_.count(key)) fail(key, "unknown key");
  }
}

}  // namespace ppp
