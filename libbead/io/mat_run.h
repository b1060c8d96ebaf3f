// A run stored in a MATLAB .mat file as matrices: `bead import RUN.mat`.
// The column mapping names variables: z an N x P matrix (or P x N: the side
// that matches the time's length N is the profiles' side), x either a
// vector of P values shared by all profiles or a matrix shaped as z, the
// time a vector of N, the encoder (optional) a vector of N whole numbers.
// Non-finite x or z are dropouts (NaN in the archive).
#pragma once

#include <string>

#include "libbead/io/import_columns.h"

namespace bead {

// Throws bead::Error naming the file and the variable.
ImportedRun ReadMatRun(const std::string& path, const ImportColumns& columns);

}  // namespace bead
