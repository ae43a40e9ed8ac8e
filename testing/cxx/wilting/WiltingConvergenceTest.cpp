// The Cucumber preset in physical units converges as the voxels shrink and means the same on leaves of other sizes
// (issue 23): the cucumber blade with its palmate veins (WiltingCucumberLeaf.h, the calibration's leaf), 10 s, the
// preset's settings (TimeStep 1/60 s, one Newton iteration), AnchorRadius 3 cm x L / 20.1. The full table (R 14-30,
// 5-40 cm) is benchmarks/wilting_convergence's (benchmarks/README.md "wilting convergence").
#include "WiltingCucumberLeaf.h"
#include "WiltingPresets.h"

#include <gtest/gtest.h>

namespace
{
using namespace plantmorph;

WiltingTipMetrics CucumberRun(const WiltingInput& leaf, double length, int resolution)
{
  WiltingParameters p;
  ApplyWiltingPreset(WiltingPreset::Cucumber, p);
  p.resolution = resolution;
  p.anchorRadius = 3.0 * length / 20.1;
  p.duration = 10.0;
  p.frameInterval = 0.1;
  p.newmark.timeStep = 1.0 / 60.0;
  p.newmark.maxIterations = 1;
  p.newmark.threads = 1;
  WiltingSimulation simulation;
  std::string error = simulation.Setup(leaf, p);
  if (error.empty())
  {
    error = simulation.Run();
  }
  return TipMetrics(simulation, length, error);
}
} // namespace

TEST(WiltingConvergence, CucumberTipPathConvergesAsResolutionGrows)
{
  // R 14, 18, 22 on the measured leaf (20.1 cm): no blow-up, 101 frames, the tip never rises back more than 5 % of
  // the length after falling, and the tip paths (in leaf lengths) draw together: the largest distance between
  // R 18's and R 22's is smaller than between R 14's and R 22's, and below 0.1 leaf lengths.
  const double length = 20.1;
  const WiltingInput leaf = CucumberBlade(length);
  ASSERT_FALSE(leaf.points.empty());
  std::vector<WiltingTipMetrics> runs;
  for (const int r : { 14, 18, 22 })
  {
    runs.push_back(CucumberRun(leaf, length, r));
    const WiltingTipMetrics& m = runs.back();
    EXPECT_EQ(m.message, "") << "R " << r;
    EXPECT_EQ(m.track.size(), 101u) << "R " << r;
    EXPECT_LT(m.risesBack, 0.05) << "R " << r;
    EXPECT_LT(m.lowest, -0.5) << "R " << r << ": the leaf wilts";
  }
  const double coarse = TrackDistance(runs[0].track, runs[2].track);
  const double fine = TrackDistance(runs[1].track, runs[2].track);
  EXPECT_LT(fine, coarse);
  EXPECT_LT(fine, 0.1);
}

TEST(WiltingConvergence, CucumberMeansTheSameOnSmallAndLargeLeaves)
{
  // 5 cm and 40 cm leaves at R 14: no blow-up, no rise beyond 5 %, and (pressures, strains and the curl being
  // scale-free with the default thickness L / 14; gravity, 1/350 of the droop's pressure on the 20 cm leaf, grows
  // as L) the tip path in leaf lengths within 0.05 of the 20.1 cm leaf's.
  const WiltingTipMetrics reference = CucumberRun(CucumberBlade(20.1), 20.1, 14);
  for (const double length : { 5.0, 40.0 })
  {
    const WiltingTipMetrics m = CucumberRun(CucumberBlade(length), length, 14);
    EXPECT_EQ(m.message, "") << length << " cm";
    EXPECT_EQ(m.track.size(), 101u) << length << " cm";
    EXPECT_LT(m.risesBack, 0.05) << length << " cm";
    EXPECT_LT(TrackDistance(m.track, reference.track), 0.05) << length << " cm";
  }
}
