// bead::Error: the one exception type of libbead. Its message names the
// file, the place in it (dataset, line, key) and what is wrong, so a user
// can fix the input without reading our code.
#pragma once

#include <stdexcept>
#include <string>

namespace bead {

class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

// "FILE: PLACE: WHAT", leaving out empty parts.
std::string Located(const std::string& file, const std::string& place, const std::string& what);

}  // namespace bead
