// The `bead` subcommands. Each Add* registers its options on the app and
// returns the function that runs it. Subcommands are thin: they parse,
// call the library, and print.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace bead::tools {

using Run = std::function<int()>;

Run AddMeasure(CLI::App& app);
Run AddSimulate(CLI::App& app);
Run AddFlow(CLI::App& app);
Run AddCalibrate(CLI::App& app);
Run AddIdentify(CLI::App& app);
Run AddExplain(CLI::App& app);
Run AddImport(CLI::App& app);
Run AddExport(CLI::App& app);
Run AddFrames(CLI::App& app);
Run AddBatch(CLI::App& app);
Run AddReport(CLI::App& app);
Run AddTune(CLI::App& app);
Run AddFeedforward(CLI::App& app);

}  // namespace bead::tools
