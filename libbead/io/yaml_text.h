// Reading YAML documents with errors that name the file and the line.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

namespace bead {

// The whole file as text; `what` says what it is for the error message.
std::string ReadTextFile(const std::string& path, const std::string& what);
// Parses YAML text; `name` (the file) is used in errors.
YAML::Node ParseYamlText(const std::string& text, const std::string& name);
// The place of an error at `node` for bead::Located: "line N: key", or
// the key alone when the node has no line (undefined, or built in code).
std::string YamlPlace(const YAML::Node& node, const std::string& key);

}  // namespace bead
