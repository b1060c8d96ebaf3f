#include <chrono>
#include <cstdio>

#include "libbead/sim/rig_simulator.h"
#include "libbead/sim/sim_writer.h"
#include "libbead/sim/part_twin_io.h"
#include "tools/commands.h"
#include "tools/subcommands.h"

namespace bead::tools {

Run AddSimulate(CLI::App& app) {
  struct Args {
    std::string config, output;
    long long seed = -1;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = app.add_subcommand("simulate", Summary("simulate"));
  cmd->footer(
      "In:  CONFIG.yaml: extruder, wheel, encoder, bead, sensor, pins, effects (every key optional;\n"
      "     testdata/configs/*.yaml show them all).\n"
      "Out: DIR/run.h5 (run archive), DIR/pins.h5 (pin scans), DIR/rig.yaml (rig file),\n"
      "     DIR/truth.h5 (true flow in extrusion time; per profile true and visible area, width,\n"
      "     height; true offset and pin positions). The same config and seed give the same bytes.\n"
      "     A config with a part: section prints a part (testdata/configs/part_wall.yaml): a wall\n"
      "     layer by layer, each bead sunk into the one below, the head's lateral error per pass,\n"
      "     the bead's wander; it writes DIR/part.h5 (part scan, format 1.1), DIR/rig.yaml (no\n"
      "     wheel) and DIR/truth.csv (per profile: layer,path_mm,area_mm2 (material),\n"
      "     visible_area_mm2, height_mm, width_mm, center_x_mm, offset_below_mm, pass_shift_mm).\n"
      "Example:\n"
      "  bead simulate testdata/configs/sample.yaml -o /tmp/sample");
  cmd->add_option("config", args->config, "Simulation config (YAML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--output", args->output, "Folder to write (created if missing)")->required();
  cmd->add_option("--seed", args->seed, "Override the config's seed");
  return [args]() {
    if (std::optional<sim::PartTwinConfig> part = sim::ReadPartTwinConfig(args->config)) {
      if (args->seed >= 0) part->seed = static_cast<uint64_t>(args->seed);
      const sim::PartTwin twin = sim::SimulatePartWall(*part);
      sim::WritePartTwin(args->output, twin);
      const bool roads = part->roads > 1;
      const std::string what =
          roads ? "a layer of " + std::to_string(part->roads) + " roads " +
                      std::to_string(part->road_spacing_mm).substr(0, 5) + " mm apart"
                : (part->shape == sim::PartTwinConfig::Shape::kContour ? "a contour with rounded corners, "
                                                                       : "a wall, ") +
                      std::to_string(part->layers) + " layers";
      std::printf("printed %s, %.0f mm of path (seed %llu): %zu profiles, %zu log samples\n", what.c_str(),
                  twin.path_length_mm, static_cast<unsigned long long>(part->seed), twin.scan.profiles.size(),
                  twin.scan.log ? twin.scan.log->size() : 0);
      std::printf("wrote %s/{part.h5, rig.yaml, truth.csv%s}\n", args->output.c_str(),
                  roads ? ", truth_roads.csv" : "");
      return 0;
    }
    sim::SimConfig config = sim::ReadSimConfig(args->config);
    if (args->seed >= 0) config.seed = static_cast<uint64_t>(args->seed);
    const auto start = std::chrono::steady_clock::now();
    const sim::SimulatedRun run = sim::Simulate(config);
    sim::WriteSimulatedRun(args->output, run);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("simulated %.1f s of the rig (seed %llu) in %.2f s: %zu profiles, %zu log samples, %zu pin scans\n",
                config.duration_s, static_cast<unsigned long long>(config.seed), seconds, run.run.profiles.size(),
                run.run.log ? run.run.log->size() : 0, run.pins.scans.size());
    std::printf("true offset %.2f counts; rig file says %.2f; total volume %.0f mm^3\n", run.truth.offset_counts,
                run.truth.rig_file_offset_counts, run.truth.total_volume_mm3);
    std::printf("wrote %s/{run.h5, pins.h5, rig.yaml, truth.h5}\n", args->output.c_str());
    return 0;
  };
}

}  // namespace bead::tools
