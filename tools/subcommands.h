// The `bead` subcommands: each is its own program, bead-<name>, beside
// `bead`, linking only what it uses (bead-measure no OpenCV, bead --help
// nothing at all); `bead` only lists them and hands over (tools/bead.cc).
#pragma once

#include <cstring>

namespace bead::tools {

struct Subcommand {
  const char* name;
  const char* summary;
};

inline constexpr Subcommand kSubcommands[] = {
    {"measure", "Bead area, width and height of every profile of a run"},
    {"flow", "Volumetric flow Q = v * A in extrusion time (thesis eq. 20)"},
    {"batch", "Geometry and flow of many runs: all cores, resumable, shardable"},
    {"calibrate", "Calibrate a rig placement"},
    {"simulate", "Simulate a run of the bead rig with a known truth (the digital twin)"},
    {"import", "Another tool's file (CSV, .mat, PLY, PCD) as a run archive"},
    {"export", "A run as a point cloud in wheel coordinates (PLY, PCD), or its profiles or log as CSV"},
    {"frames", "Camera frames of the laser stripe as a run archive"},
    {"identify", "Identify a transfer function (poles, zeros, delay) from data"},
    {"explain", "Find what the model lacks: residual diagnostics and effects added"},
    {"report", "One self-contained HTML page about a run: profiles, geometry, flow, pins"},
    {"tune", "A PID from a model: maximum stability degree, SIMC, IMC, ZN, Cohen-Coon"},
    {"feedforward", "The wheel command that holds a bead area for a planned extruder command"},
};

inline const char* Summary(const char* name) {
  for (const Subcommand& s : kSubcommands)
    if (std::strcmp(s.name, name) == 0) return s.summary;
  return "";
}

}  // namespace bead::tools
