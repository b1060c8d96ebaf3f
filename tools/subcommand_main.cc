// main() of one subcommand's program, bead-<name> (built once per
// subcommand with BEAD_SUBCOMMAND_ADD naming its Add* function). `bead`
// hands over to it with argv = {"bead", "<name>", ...}. Every error is one
// line naming the file and place (exit 1); usage errors exit 2.
#include <cstdio>
#include <exception>

#include "libbead/core/error.h"
#include "tools/commands.h"

int main(int argc, char** argv) {
  CLI::App app{"bead: bead cross-sections and volumetric flow from laser line profiles (libbead)", "bead"};
  app.footer("Run 'bead --help' for the list of subcommands.");
  app.require_subcommand(1);
  const bead::tools::Run run = bead::tools::BEAD_SUBCOMMAND_ADD(app);
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
