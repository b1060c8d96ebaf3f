#include "libbead/io/yaml_text.h"

#include <fstream>
#include <sstream>

#include "libbead/core/error.h"

namespace bead {

std::string ReadTextFile(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw Error(Located(path, "", "cannot open " + what));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

YAML::Node ParseYamlText(const std::string& text, const std::string& name) {
  try {
    return YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw Error(Located(name, "line " + std::to_string(e.mark.line + 1), "not valid YAML: " + e.msg));
  }
}

std::string YamlPlace(const YAML::Node& node, const std::string& key) {
  if (node.IsDefined() && node.Mark().line >= 0) return "line " + std::to_string(node.Mark().line + 1) + ": " + key;
  return key;
}

}  // namespace bead
