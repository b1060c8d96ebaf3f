// bead-measure, bead-flow and bead-batch load the occlusion fit (Ceres) as
// a module when a fit runs (tools/occlusion_module.h). What comes back
// across that boundary is what the linked fit gives.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "libbead/archive/measure_run.h"
#include "libbead/io/geometry_csv.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/occlusion/occlusion_fit.h"
#include "tests/support/temp_dir.h"

namespace bead {
namespace {

// `bead measure` takes its fit from the module it loads when a fit runs
// (tools/occlusion_module.h); across that boundary the fit is the linked
// one: the same geometry CSV byte for byte, fitted per profile and pooled.
TEST(OcclusionModule, TheToolsLoadedFitIsTheLinkedOne) {
  test::TempDir dir;
  const std::string sample = std::string(BEAD_SOURCE_DIR) + "/testdata/sample/";
  const Rig rig = ReadRig(sample + "rig.yaml");
  for (const OcclusionMode mode : {OcclusionMode::kEach, OcclusionMode::kPooled}) {
    const std::string name = mode == OcclusionMode::kEach ? "each" : "pooled";
    WorkerPool pool(2);
    ProfileStream stream(sample + "run.h5", pool);
    MeasureRunOptions options;
    options.occlusion = mode;
    options.estimate = occlusion::EstimateOcclusion;
    std::vector<GeometryRow> rows;
    MeasureRun(stream, rig, pool, options, [&](const GeometryRow& r) { rows.push_back(r); });
    WriteGeometryCsv(dir / ("linked_" + name + ".csv"), rows);
    const std::string cmd = std::string(BEAD_CLI) + " measure --rig " + sample + "rig.yaml " + sample +
                            "run.h5 --occlusion " + name + " -o " + (dir / ("tool_" + name + ".csv")) + " > " +
                            (dir / "out.txt") + " 2>&1";
    ASSERT_EQ(std::system(cmd.c_str()), 0) << test::ReadText(dir / "out.txt");
    const std::string linked = test::ReadText(dir / ("linked_" + name + ".csv"));
    EXPECT_GT(linked.size(), 1000u);
    EXPECT_TRUE(linked == test::ReadText(dir / ("tool_" + name + ".csv"))) << name;
  }
}

}  // namespace
}  // namespace bead
