// MATLAB .mat files (v4, v5, v7.3 as Debian's libmatio reads them): the
// real numeric vectors they hold, by name, for the commands that take
// measured series (identify, explain); and one numeric matrix by name, for
// runs whose profiles are stored as matrices (`bead import`). What a reader cannot use (MATLAB
// objects, cells, structs, strings, matrices, a function workspace, a
// name written twice) is skipped and listed, never an error by itself.
#pragma once

#include <string>
#include <vector>

namespace bead {

struct MatVector {
  std::string name;
  std::vector<double> values;  // converted from the stored class (double, single, integers)
};

struct MatContents {
  std::vector<MatVector> vectors;    // in file order, the first of a repeated name
  std::vector<std::string> skipped;  // "name: why"
  const MatVector* Find(const std::string& name) const;
  std::string Names() const;  // the usable vectors' names, comma separated
};

struct MatMatrix {
  std::string name;
  std::size_t rows = 0, cols = 0;
  std::vector<double> values;  // column-major, as MATLAB stores it: (r, c) at r + rows * c
  double at(std::size_t r, std::size_t c) const { return values[r + rows * c]; }
};

// Reads the real numeric variable `name` of at most two dimensions (a
// vector is a 1 x n or n x 1 matrix). Throws bead::Error naming the file
// and the variable, listing the numeric variables there are, when it is
// missing, not numeric, complex or of more dimensions.
MatMatrix ReadMatMatrix(const std::string& path, const std::string& name);

// Reads every usable vector (all of them: small acquisition files).
// Throws bead::Error naming the file when it is no .mat file.
MatContents ReadMatVectors(const std::string& path);

}  // namespace bead
