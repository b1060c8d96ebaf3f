#include "tools/subcommand_main.h"

#include <cstdio>
#include <exception>

#include "libbead/core/error.h"
#include "tools/commands.h"

namespace bead::tools {

int SubcommandMain(int argc, char** argv, AddSubcommand add) {
  CLI::App app{"bead: bead cross-sections and volumetric flow from laser line profiles (libbead)", "bead"};
  app.footer("Run 'bead --help' for the list of subcommands.");
  app.require_subcommand(1);
  const Run run = add(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    return run();
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bead: error: %s\n", e.what());
    return 1;
  }
}

}  // namespace bead::tools
