#pragma once
// Reading one YAML document the way every YAML the project reads is read
// (configuration files, simulation configurations, campaign manifests): syntax
// errors and keys written twice in one mapping are ConfigError naming the file
// and the line. yaml-cpp keeps both entries of a key written twice and its
// lookups return the first, so a second `measurement_model:` section would be
// ignored without a word: the document is refused instead.
//
// The duplicate check walks the parser's events (not the node tree), so it
// sees every mapping exactly as written, aliases included once, in time
// linear in the text.
#include <string>

#include <yaml-cpp/yaml.h>

#include "ppp_bayes_tree/ppp/config/yaml_section.h"  // ConfigError

namespace ppp {

/// Throws ConfigError(source_name, key path, "key given twice in one mapping, at
/// line A and line B ...") for the first key that appears twice in one mapping of
/// the first document of `yaml_text`. The key path is "a.b.c" ("a[2].b" inside
/// sequences). Does nothing for text that does not parse (the loader reports it).
void rejectDuplicateYamlKeys(const std::string& yaml_text, const std::string& source_name);

/// The first document of `yaml_text`: syntax errors as ConfigError(source_name,
/// "", "YAML syntax error at line N: ..."), then rejectDuplicateYamlKeys.
YAML::Node parseYamlDocument(const std::string& yaml_text, const std::string& source_name);

/// The file read whole, then parseYamlDocument naming `path`. Throws ConfigError
/// "cannot open the file" or "read error".
YAML::Node loadYamlDocument(const std::string& path);

}  // namespace ppp
