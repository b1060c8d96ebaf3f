// A run stored as matrices in a .mat file (bead import RUN.mat), and the
// vectors identify and explain read from one. Variables Z, X, t, enc as the
// seeds name them. libmatio's own crashes on a corrupt file are told apart
// by scripts/fuzz.sh, as libhdf5's are.
#include "fuzz/fuzz_input.h"
#include "libbead/core/error.h"
#include "libbead/io/mat_file.h"
#include "libbead/io/mat_run.h"

namespace {
bead::ImportColumns Columns() {
  bead::ImportColumns c;
  c.time = "t";
  c.x = "X";
  c.z = "Z";
  c.encoder = "enc";
  return c;
}
}  // namespace

BEAD_FUZZ_READER(".mat", {
  bead::ReadMatRun(path, Columns());
  bead::ReadMatVectors(path);
})
