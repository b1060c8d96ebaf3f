#include "libbead/core/error.h"

namespace bead {

std::string Located(const std::string& file, const std::string& place, const std::string& what) {
  std::string out;
  if (!file.empty()) out += file + ": ";
  if (!place.empty()) out += place + ": ";
  return out + what;
}

}  // namespace bead
