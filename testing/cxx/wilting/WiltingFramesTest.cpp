// SPDX-License-Identifier: GPL-3.0-or-later
// What WiltingSimulator plays and says, in the core: the frame times it advertises before simulating, the state
// between two frames, the assumptions it warns about, and the text of a named preset's values.
#include "WiltingFrames.h"
#include "WiltingPresets.h"
#include "WiltingSimulation.h"
#include "WiltingTestBlades.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <map>
#include <sstream>
#include <string>

namespace
{
using namespace plantmorph;

WiltingParameters Timing(double duration, double timeStep, double frameInterval)
{
  WiltingParameters p;
  p.duration = duration;
  p.newmark.timeStep = timeStep;
  p.frameInterval = frameInterval;
  return p;
}

TEST(WiltingFrames, TimesAreWholeStepsEveryFrameIntervalUpToTheDuration)
{
  // 0.1 s frames of 0.01 s steps over 1 s: 11 frames, k * 10 steps each.
  std::vector<double> times = WiltingFrameTimes(Timing(1.0, 0.01, 0.1));
  ASSERT_EQ(times.size(), 11u);
  for (std::size_t k = 0; k < times.size(); ++k)
  {
    EXPECT_EQ(times[k], static_cast<double>(k * 10) * 0.01);
  }
  // A frame interval that is not a whole number of steps is rounded to one: 0.3 s of 0.125 s steps -> 0.25 s frames.
  times = WiltingFrameTimes(Timing(1.0, 0.125, 0.3));
  ASSERT_EQ(times.size(), 5u);
  EXPECT_EQ(times[1], 0.25);
  EXPECT_EQ(times.back(), 1.0);
  // A frame interval shorter than a step still advances a step per frame.
  times = WiltingFrameTimes(Timing(0.5, 0.1, 0.01));
  ASSERT_EQ(times.size(), 6u);
  EXPECT_NEAR(times[1], 0.1, 1e-15);
  // Parameters the simulation rejects advertise no times.
  EXPECT_TRUE(WiltingFrameTimes(Timing(1.0, -0.1, 0.1)).empty());
  EXPECT_FALSE(ValidateWilting(Timing(1.0, -0.1, 0.1)).empty());
}

/// Two nodes, frames at `times`, frame f's q and v all equal to f + 1 and -(f + 1).
std::vector<WiltingFrame> Frames(const std::vector<double>& times)
{
  std::vector<WiltingFrame> frames(times.size());
  for (std::size_t f = 0; f < times.size(); ++f)
  {
    frames[f].time = times[f];
    frames[f].q.assign(6, static_cast<double>(f + 1));
    frames[f].v.assign(6, -static_cast<double>(f + 1));
  }
  return frames;
}

TEST(WiltingFrames, StateIsLinearBetweenFramesAndClampedOutside)
{
  const std::vector<WiltingFrame> frames = Frames({ 0.0, 0.5, 1.0 });
  // A frame's own time gives that frame exactly.
  WiltingNodeState state = InterpolateWiltingFrames(frames, 0.5, 2);
  EXPECT_EQ(state.time, 0.5);
  ASSERT_EQ(state.q.size(), 6u);
  EXPECT_EQ(state.q[0], 2.0);
  EXPECT_EQ(state.v[5], -2.0);
  // A quarter of the way from 0.5 to 1.0.
  state = InterpolateWiltingFrames(frames, 0.625, 2);
  EXPECT_DOUBLE_EQ(state.time, 0.625);
  EXPECT_DOUBLE_EQ(state.q[3], 2.25);
  EXPECT_DOUBLE_EQ(state.v[3], -2.25);
  // Before the first frame and after the last: those frames.
  state = InterpolateWiltingFrames(frames, -3.0, 2);
  EXPECT_EQ(state.time, 0.0);
  EXPECT_EQ(state.q[0], 1.0);
  state = InterpolateWiltingFrames(frames, 7.0, 2);
  EXPECT_EQ(state.time, 1.0);
  EXPECT_EQ(state.q[0], 3.0);
  // One frame (a run stopped at its first step): always it.
  state = InterpolateWiltingFrames(Frames({ 0.0 }), 0.3, 2);
  EXPECT_EQ(state.time, 0.0);
  EXPECT_EQ(state.v[1], -1.0);
}

TEST(WiltingInputAssumptions, CountsEdgesOfMoreThanTwoTrianglesAndSaysWhatIsAssumed)
{
  // Two triangles on the edge 0-1: manifold; a third on it: one non-manifold edge.
  std::vector<std::array<int, 3>> triangles = { { 0, 1, 2 }, { 1, 0, 3 } };
  EXPECT_EQ(CountNonManifoldEdges(triangles), 0u);
  triangles.push_back({ 0, 1, 4 });
  EXPECT_EQ(CountNonManifoldEdges(triangles), 1u);
  triangles.push_back({ 4, 1, 5 }); // 1-4 now has two, 0-1 still three
  EXPECT_EQ(CountNonManifoldEdges(triangles), 1u);

  WiltingInput blade = GridBlade(2.0, 4.0, 2, 4, [](int, int) { return 0; });
  ASSERT_FALSE(blade.leafUV.empty());
  EXPECT_EQ(WiltingInputAssumptions(blade, true), "");
  const std::string noRegion = WiltingInputAssumptions(blade, false);
  EXPECT_NE(noRegion.find("no Region point array"), std::string::npos);
  EXPECT_EQ(noRegion.find("LeafUV"), std::string::npos);
  EXPECT_NE(noRegion.back(), ' ');
  blade.leafUV.clear();
  blade.triangles.push_back(blade.triangles.front());
  blade.triangles.push_back(blade.triangles.front());
  const std::string all = WiltingInputAssumptions(blade, false);
  EXPECT_LT(all.find("no LeafUV"), all.find("no Region"));
  EXPECT_NE(all.find("not a manifold surface (3 edge(s)"), std::string::npos);
}

TEST(WiltingPresets, DescriptionGivesEveryValueThePresetSetsDigitForDigit)
{
  for (WiltingPreset preset : { WiltingPreset::Cucumber, WiltingPreset::Tomato, WiltingPreset::Watermelon })
  {
    WiltingParameters p;
    ApplyWiltingPreset(preset, p);
    const std::string text = DescribeWiltingPreset(preset);
    EXPECT_EQ(text.rfind(WiltingPresetName(preset) + " sets", 0), 0u) << text;
    std::istringstream lines(text);
    std::string line;
    std::map<std::string, std::string> values;
    while (std::getline(lines, line))
    {
      const std::size_t eq = line.find(" = ");
      if (eq != std::string::npos)
      {
        values[line.substr(0, eq)] = line.substr(eq + 3);
      }
    }
    EXPECT_EQ(values.size(), 26u);
    // Values read back exactly.
    EXPECT_EQ(std::strtod(values["DroopForce"].c_str(), nullptr), p.droopForce);
    EXPECT_EQ(std::strtod(values["RayleighBeta"].c_str(), nullptr), p.newmark.rayleighStiffness);
    EXPECT_EQ(std::strtod(values["CurlStrain"].c_str(), nullptr), p.curlStrain);
    const std::string& blade = values["BladeMaterial"];
    const std::size_t comma = blade.find(", ");
    EXPECT_EQ(std::strtod(blade.substr(comma + 2).c_str(), nullptr), p.materials[WiltingBlade].stiffness);
    EXPECT_EQ(values["LoadProfile"], std::to_string(static_cast<int>(p.loadProfile)));
  }
}
} // namespace
