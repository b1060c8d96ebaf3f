// Reading YAML documents with errors that name the file and the line.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

namespace bead {

// The whole file as text; `what` says what it is for the error message.
std::string ReadTextFile(const std::string& path, const std::string& what);
// Parses YAML text; `name` (the file) is used in errors.
YAML::Node ParseYamlText(const std::string& text, const std::string& name);

}  // namespace bead
