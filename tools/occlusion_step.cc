#include "tools/occlusion_step.h"

namespace bead::tools {

void AddOcclusionOption(CLI::App* cmd, std::string& mode) {
  cmd->add_option("--occlusion", mode,
                  "Hidden-area correction: pooled (one shape per run), each (a fit per profile), none")
      ->capture_default_str()
      ->check(CLI::IsMember({"pooled", "each", "none"}));
}

}  // namespace bead::tools
