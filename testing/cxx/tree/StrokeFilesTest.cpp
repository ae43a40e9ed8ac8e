// SPDX-License-Identifier: GPL-3.0-or-later
// Stroke files (sources/tree/core/StrokeFiles.h): SVG as drawing programs write it, with exact expected points, and
// hostile files refused with a clear error and no strokes.
#include "StrokeFiles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace plantmorph;

namespace
{
using Strokes = std::vector<std::vector<Eigen::Vector3d>>;

const char* const kInkscapeHead = R"~(<?xml version="1.0" encoding="UTF-8" standalone="no"?>
<!-- Created with Inkscape (http://www.inkscape.org/) -->

<svg
   width="100mm"
   height="50mm"
   viewBox="0 0 200 100"
   version="1.1"
   id="svg5"
   inkscape:version="1.2.2 (b0a8486541, 2022-12-01)"
   sodipodi:docname="strokes.svg"
   xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape"
   xmlns:sodipodi="http://sodipodi.sourceforge.net/DTD/sodipodi-0.dtd"
   xmlns="http://www.w3.org/2000/svg"
   xmlns:svg="http://www.w3.org/2000/svg">
  <sodipodi:namedview
     id="namedview7"
     pagecolor="#ffffff"
     inkscape:document-units="mm" />
  <defs
     id="defs2">
    <path id="notDrawn" d="M 0,0 L 5,5" />
  </defs>
)~";

/// An SVG of user units = output units (no viewBox) around `body`.
std::string Plain(const std::string& body)
{
  return "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"400\" height=\"400\">" + body + "</svg>";
}

Eigen::Vector3d Flip(const Eigen::Vector2d& p)
{
  return Eigen::Vector3d(p.x(), -p.y(), 0.0);
}

Eigen::Vector2d Cubic(
  const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c, const Eigen::Vector2d& d, double t)
{
  // de Casteljau, independent of the reader's Bernstein form
  const Eigen::Vector2d ab = a + t * (b - a), bc = b + t * (c - b), cd = c + t * (d - c);
  const Eigen::Vector2d abc = ab + t * (bc - ab), bcd = bc + t * (cd - bc);
  return abc + t * (bcd - abc);
}

double SegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

/// Largest distance from the curve (dense samples) to the polyline (output coordinates, y flipped back).
template <typename Curve>
double Deviation(const std::vector<Eigen::Vector3d>& stroke, Curve curve)
{
  double worst = 0.0;
  for (int k = 0; k <= 2000; ++k)
  {
    const Eigen::Vector2d p = curve(k / 2000.0);
    double best = HUGE_VAL;
    for (std::size_t i = 0; i + 1 < stroke.size(); ++i)
    {
      best = std::min(best,
        SegmentDistance(
          p, Eigen::Vector2d(stroke[i].x(), -stroke[i].y()), Eigen::Vector2d(stroke[i + 1].x(), -stroke[i + 1].y())));
    }
    worst = std::max(worst, best);
  }
  return worst;
}

void ExpectNear(const Eigen::Vector3d& actual, const Eigen::Vector3d& expected, double tolerance = 1e-12)
{
  EXPECT_NEAR(actual.x(), expected.x(), tolerance * (1.0 + std::abs(expected.x()))) << actual.transpose();
  EXPECT_NEAR(actual.y(), expected.y(), tolerance * (1.0 + std::abs(expected.y()))) << actual.transpose();
  EXPECT_EQ(actual.z(), 0.0);
}

void ExpectRefused(const std::string& svg, const std::string& words)
{
  Strokes strokes;
  const std::string error = ParseStrokeSvg(svg, strokes);
  EXPECT_NE(error.find(words), std::string::npos) << error;
  EXPECT_EQ(error.rfind("StrokeFile: ", 0), 0u) << error;
  EXPECT_TRUE(strokes.empty());
}
} // namespace

TEST(StrokeFiles, InkscapeLayerWithViewBoxUnitsAndRelativeCommands)
{
  // Inkscape's defaults: page in mm through a viewBox, relative commands with implicit repetition, a layer group
  // with a translate. 200 x 100 user units on 100 mm x 50 mm: s = (100 * 96 / 25.4) / 200 px per unit.
  const std::string svg = std::string(kInkscapeHead) + R"~(  <g
     inkscape:label="Layer 1"
     inkscape:groupmode="layer"
     id="layer1"
     transform="translate(10,20)">
    <path
       style="fill:none;stroke:#000000;stroke-width:0.264583px"
       d="m 20,30 40,0 0,10 h -5 v 5 z"
       id="path111" />
  </g>
</svg>
)~";
  Strokes strokes;
  ASSERT_EQ(ParseStrokeSvg(svg, strokes), "");
  ASSERT_EQ(strokes.size(), 1u); // the path in <defs> is not drawn
  const double s = (100.0 * 96.0 / 25.4) / 200.0;
  const std::vector<Eigen::Vector2d> user = { { 20, 30 }, { 60, 30 }, { 60, 40 }, { 55, 40 }, { 55, 45 }, { 20, 30 } };
  ASSERT_EQ(strokes[0].size(), user.size());
  for (std::size_t i = 0; i < user.size(); ++i)
  {
    ExpectNear(strokes[0][i], Flip(s * (user[i] + Eigen::Vector2d(10, 20))));
  }
}

TEST(StrokeFiles, TheBowStaysABow)
{
  const Eigen::Vector2d p0(0, 100), p1(40, 66), p2(40, 33), p3(0, 0);
  Strokes absolute, relative;
  ASSERT_EQ(ParseStrokeSvg(Plain(R"~(<path d="M 0,100 C 40,66 40,33 0,0"/>)~"), absolute), "");
  ASSERT_EQ(ParseStrokeSvg(Plain(R"~(<path d="m 0,100 c 40,-34 40,-67 0,-100"/>)~"), relative), "");
  ASSERT_EQ(absolute.size(), 1u);
  const auto& bow = absolute[0];
  // n = ceil(sqrt(6 * max|P0 - 2 P1 + P2|, |P1 - 2 P2 + P3|) / (8 * 0.1))) = ceil(sqrt(240.07 / 0.8)) = 18 chords.
  ASSERT_EQ(bow.size(), 19u);
  for (int k = 0; k <= 18; ++k)
  {
    ExpectNear(bow[static_cast<std::size_t>(k)], Flip(Cubic(p0, p1, p2, p3, k / 18.0)));
  }
  EXPECT_EQ(bow.front(), Eigen::Vector3d(0, -100, 0));
  EXPECT_EQ(bow.back(), Eigen::Vector3d(0, 0, 0));
  EXPECT_NEAR(bow[9].x(), 30.0, 1e-12); // B(1/2) = (P0 + 3 P1 + 3 P2 + P3) / 8 = (30, 49.625)
  EXPECT_NEAR(bow[9].y(), -49.625, 1e-12);
  EXPECT_LE(Deviation(bow, [&](double t) { return Cubic(p0, p1, p2, p3, t); }), kSvgCurveTolerance);
  ASSERT_EQ(relative.size(), 1u);
  ASSERT_EQ(relative[0].size(), bow.size());
  for (std::size_t i = 0; i < bow.size(); ++i)
  {
    ExpectNear(relative[0][i], bow[i]);
  }
}

TEST(StrokeFiles, SmoothCurvesReflectTheirControlPoints)
{
  Strokes strokes;
  ASSERT_EQ(ParseStrokeSvg(Plain(R"~(<path d="M0,0 C0,10 10,10 10,0 S20,-10 20,0"/>)~"), strokes), "");
  ASSERT_EQ(strokes.size(), 1u);
  // The second curve's first control point is (10,10) reflected about (10,0): (10,-10).
  const auto second = [](double t) { return Cubic({ 10, 0 }, { 10, -10 }, { 20, -10 }, { 20, 0 }, t); };
  const auto& s = strokes[0];
  EXPECT_EQ(s.back(), Eigen::Vector3d(20, -0.0, 0));
  EXPECT_LE(Deviation(s, second), kSvgCurveTolerance);
  EXPECT_LE(Deviation(s,
              [](double t) {
                return Cubic({ 0, 0 }, { 0, 10 }, { 10, 10 }, { 10, 0 }, t);
              }),
    kSvgCurveTolerance);
  bool sawReflected = false; // a point on the second curve's lower half (y < 0 in SVG, > 0 here)
  for (const auto& p : s)
    sawReflected = sawReflected || (p.x() > 10.5 && p.y() > 7.0);
  EXPECT_TRUE(sawReflected);

  ASSERT_EQ(ParseStrokeSvg(Plain(R"~(<path d="M0,0 Q5,10 10,0 T20,0"/>)~"), strokes), "");
  const auto quadratic = [](Eigen::Vector2d a, Eigen::Vector2d b, Eigen::Vector2d c, double t) -> Eigen::Vector2d {
    return (1 - t) * (1 - t) * a + 2 * (1 - t) * t * b + t * t * c;
  };
  // T reflects (5,10) about (10,0): (15,-10). |P0 - 2 P1 + P2| = 20: n = ceil(sqrt(40 / 0.8)) = 8 chords each.
  ASSERT_EQ(strokes[0].size(), 17u);
  for (int k = 0; k <= 8; ++k)
  {
    ExpectNear(strokes[0][static_cast<std::size_t>(k)], Flip(quadratic({ 0, 0 }, { 5, 10 }, { 10, 0 }, k / 8.0)));
    ExpectNear(
      strokes[0][static_cast<std::size_t>(8 + k)], Flip(quadratic({ 10, 0 }, { 15, -10 }, { 20, 0 }, k / 8.0)));
  }
}

TEST(StrokeFiles, ArcsLieOnTheirEllipse)
{
  Strokes strokes;
  // Half circle of radius 10 about the origin, from angle 0 through (0,10) (sweep 1: increasing angle in SVG's
  // y-down frame). n = ceil(sqrt(10 * pi^2 / 0.8)) = 12 chords.
  ASSERT_EQ(ParseStrokeSvg(Plain(R"~(<path d="M 10,0 A 10,10 0 0 1 -10,0"/>)~"), strokes), "");
  ASSERT_EQ(strokes[0].size(), 13u);
  for (int k = 0; k <= 12; ++k)
  {
    const double t = M_PI * k / 12.0;
    ExpectNear(
      strokes[0][static_cast<std::size_t>(k)], Flip(Eigen::Vector2d(10 * std::cos(t), 10 * std::sin(t))), 1e-13);
  }
  // Radii too small for the end points are scaled up (to 5 here, centre (5,0)); sweep 0 goes the other way round;
  // relative end point and flags written without separators.
  ASSERT_EQ(ParseStrokeSvg(Plain(R"~(<path d="M0,0a1,1 0 0010,0"/>)~"), strokes), "");
  const auto& s = strokes[0];
  EXPECT_EQ(s.back(), Eigen::Vector3d(10, -0.0, 0));
  for (const auto& p : s)
  {
    EXPECT_NEAR(std::hypot(p.x() - 5.0, p.y()), 5.0, 1e-12);
    EXPECT_LE(p.y(), 1e-12); // sweep 0 (decreasing angle) from (0,0) to (10,0) passes (5,5) in SVG, (5,-5) here
  }
  // A rotated ellipse: every point satisfies the ellipse equation in the rotated frame.
  ASSERT_EQ(ParseStrokeSvg(Plain(R"~(<path d="M 0,0 A 20 10 30 1 1 10,5"/>)~"), strokes), "");
  EXPECT_GT(strokes[0].size(), 10u);
  EXPECT_EQ(strokes[0].back(), Eigen::Vector3d(10, -5, 0));
}

TEST(StrokeFiles, ArcsOfHugeRadiusAreStraightLines)
{
  Strokes strokes;
  for (const char* radius : { "1e155", "1e200", "1e300", "1e80" })
  {
    const std::string d = std::string("M 0,0 A ") + radius + "," + radius + " 0 0 1 10,0 L 10,10";
    ASSERT_EQ(ParseStrokeSvg(Plain("<path d=\"" + d + "\"/>"), strokes), "") << radius;
    ASSERT_EQ(strokes.size(), 1u);
    EXPECT_EQ(strokes[0], (std::vector<Eigen::Vector3d>{ { 0, 0, 0 }, { 10, 0, 0 }, { 10, -10, 0 } })) << radius;
  }
}

TEST(StrokeFiles, NestedSvgViewportsApplyTheirPositionAndViewBox)
{
  Strokes strokes;
  // The inner viewport at (100, 50) maps its viewBox 0 0 10 10 onto 20 x 20: scale 2.
  ASSERT_EQ(ParseStrokeSvg(Plain(R"~(<svg x="100" y="50" width="20" height="20" viewBox="0 0 10 10">
      <line x1="1" y1="2" x2="3" y2="4"/></svg>
    <svg x="5"><line x1="0" y1="0" x2="1" y2="0"/></svg>)~"),
              strokes),
    "");
  ASSERT_EQ(strokes.size(), 2u);
  ExpectNear(strokes[0][0], Eigen::Vector3d(102, -54, 0));
  ExpectNear(strokes[0][1], Eigen::Vector3d(106, -58, 0));
  ExpectNear(strokes[1][0], Eigen::Vector3d(5, 0, 0));
  EXPECT_NE(ParseStrokeSvg(Plain(R"~(<svg viewBox="0 0 -1 1"><line x1="0" y1="0" x2="1" y2="0"/></svg>)~"), strokes)
              .find("viewBox"),
    std::string::npos);
  EXPECT_TRUE(strokes.empty());
}

TEST(StrokeFiles, ErrorsAboutStrokesNameTheFileAndTheirLineOrElement)
{
  Strokes strokes;
  std::vector<std::string> origins;
  ASSERT_EQ(ParseStrokeCsv("stroke_id,x,y\n7,0,0\n7,0,1\n# c\n3,2,2\n3,2,2\n", strokes, &origins), "");
  ASSERT_EQ(origins, (std::vector<std::string>{ "stroke_id '7' from line 2", "stroke_id '3' from line 5" }));
  EXPECT_EQ(StrokeFileError("Strokes input, stroke 1: has zero length", "a.csv", origins),
    "StrokeFile 'a.csv', stroke 1 (stroke_id '3' from line 5): has zero length");
  EXPECT_EQ(StrokeFileError("Strokes input: no strokes", "a.csv", origins), "StrokeFile 'a.csv': no strokes");
  EXPECT_EQ(StrokeFileError("Angle is out of range", "a.csv", origins), "Angle is out of range");
  ASSERT_EQ(ParseStrokeSvg(
              Plain("<path id=\"p\" d=\"M 0 0 L 1 1 M 2 2 L 3 3\"/>\n<line x1=\"1\" x2=\"1\"/>"), strokes, &origins),
    "");
  ASSERT_EQ(origins.size(), 3u);
  EXPECT_EQ(origins[1].rfind("the SVG element <path id=\"p\"> (line ", 0), 0u) << origins[1];
  EXPECT_NE(origins[1].find(", subpath 2"), std::string::npos) << origins[1];
  EXPECT_EQ(origins[2].rfind("the SVG element <line> (line ", 0), 0u) << origins[2];
}

TEST(StrokeFiles, NestedTransformsAndElements)
{
  Strokes strokes;
  ASSERT_EQ(ParseStrokeSvg(Plain(R"~(
    <g transform="translate(100,0) scale(2)"><g transform="rotate(90)"><polyline points="1,0 2,0"/></g></g>
    <line x1="0" y1="1" x2="0" y2="2" transform="skewX(45)"/>
    <polygon points="0,0 1,0 1,1" transform="matrix(1 0 0 1 5 6)"/>
    <g transform="rotate(180 1 1) skewY(0)"><line x1="0" y1="0" x2="2" y2="0"/></g>
    <rect x="0" y="0" width="5" height="5"/>
    <path d="M 1 1 L 2 2 M 3 3 L 4 4"/>)~"),
              strokes),
    "");
  ASSERT_EQ(strokes.size(), 6u);
  ExpectNear(strokes[0][0], Eigen::Vector3d(100, -2, 0)); // (1,0) rotated to (0,1), scaled (0,2), moved
  ExpectNear(strokes[0][1], Eigen::Vector3d(100, -4, 0));
  ExpectNear(strokes[1][0], Eigen::Vector3d(1, -1, 0)); // skewX(45): x' = x + y
  ExpectNear(strokes[1][1], Eigen::Vector3d(2, -2, 0));
  ASSERT_EQ(strokes[2].size(), 4u); // the polygon is closed
  ExpectNear(strokes[2][0], Eigen::Vector3d(5, -6, 0));
  ExpectNear(strokes[2][2], Eigen::Vector3d(6, -7, 0));
  ExpectNear(strokes[2][3], Eigen::Vector3d(5, -6, 0));
  ExpectNear(strokes[3][0], Eigen::Vector3d(2, -2, 0)); // rotate(180) about (1,1)
  ExpectNear(strokes[3][1], Eigen::Vector3d(0, -2, 0));
  EXPECT_EQ(strokes[4], (std::vector<Eigen::Vector3d>{ { 1, -1, 0 }, { 2, -2, 0 } })); // subpaths are strokes
  EXPECT_EQ(strokes[5], (std::vector<Eigen::Vector3d>{ { 3, -3, 0 }, { 4, -4, 0 } }));
}

TEST(StrokeFiles, PathGrammarCorners)
{
  Strokes strokes;
  // Numbers glued as SVG allows, implicit linetos after a moveto, relative commands after z start at the subpath's
  // first point.
  ASSERT_EQ(ParseStrokeSvg(Plain(R"~(<path d="M1-2.5.5.25L3,4 5,6z l1,1"/>)~"), strokes), "");
  EXPECT_EQ(strokes[0],
    (std::vector<Eigen::Vector3d>{
      { 1, 2.5, 0 }, { 0.5, -0.25, 0 }, { 3, -4, 0 }, { 5, -6, 0 }, { 1, 2.5, 0 }, { 2, 1.5, 0 } }));
  ExpectRefused(Plain(R"~(<path id="p7" d="M 0 0 X 5 5"/>)~"), "<path id=\"p7\">");
  ExpectRefused(Plain(R"~(<path d="L 0 0"/>)~"), "must start with M");
  ExpectRefused(Plain(R"~(<path d="M 0 0 C 1 1 2"/>)~"), "'C' command needs 6 numbers");
  ExpectRefused(Plain(R"~(<path d="M 0 0 Z 5 5"/>)~"), "a number after Z");
  ExpectRefused(Plain(R"~(<path d="M 0 0 A 1 1 0 2 0 5 5"/>)~"), "arc flag");
  ExpectRefused(Plain(R"~(<polyline points="0,0 1"/>)~"), "pairs of numbers");
  ExpectRefused(Plain(R"~(<g transform="translate(1,2"><path d="M 0 0 L 1 1"/></g>)~"), "transform");
  ExpectRefused(Plain(R"~(<g transform="spin(3)"><path d="M 0 0 L 1 1"/></g>)~"), "transform");
  ExpectRefused("<html><path d=\"M 0 0 L 1 1\"/></html>", "not <svg>");
  ExpectRefused(Plain(""), "no <path");
}

TEST(StrokeFiles, ViewBoxAspectRatio)
{
  Strokes strokes;
  const auto point = [&](const std::string& attributes) {
    const std::string svg = "<svg " + attributes + "><polyline points=\"2,2 3,3\"/></svg>";
    EXPECT_EQ(ParseStrokeSvg(svg, strokes), "") << svg;
    return strokes.empty() ? Eigen::Vector3d::Zero().eval() : strokes[0][0];
  };
  // 10 x 10 user units on 100 x 50 px: meet scales by 5 and centres (x offset 25).
  ExpectNear(point(R"~(width="100" height="50" viewBox="0 0 10 10")~"), Eigen::Vector3d(35, -10, 0));
  ExpectNear(
    point(R"~(width="100" height="50" viewBox="0 0 10 10" preserveAspectRatio="none")~"), Eigen::Vector3d(20, -10, 0));
  ExpectNear(point(R"~(width="100" height="50" viewBox="0 0 10 10" preserveAspectRatio="xMinYMin slice")~"),
    Eigen::Vector3d(20, -20, 0));
  ExpectNear(point(R"~(width="100" height="50" viewBox="0 0 10 10" preserveAspectRatio="xMaxYMax")~"),
    Eigen::Vector3d(60, -10, 0));
  ExpectNear(point(R"~(width="1in" height="25.4mm" viewBox="1,1,96,96")~"), Eigen::Vector3d(1, -1, 0));
  ExpectNear(point(R"~(width="100%" viewBox="-2 -2 4 4")~"), Eigen::Vector3d(4, -4, 0)); // percent: the viewBox's size
  ExpectNear(point(R"~(width="100mm" height="100mm")~"), Eigen::Vector3d(2, -2, 0));     // no viewBox: user units
  ExpectRefused(R"~(<svg viewBox="0 0 0 10"><line x2="1"/></svg>)~", "viewBox");
  ExpectRefused(R"~(<svg viewBox="0 0 10 10" width="wide"><line x2="1"/></svg>)~", "width");
}

TEST(StrokeFiles, LongElementsAsDigitisersWriteThem)
{
  // The former crashes: 2,000-point polyline (27 KB), 5,000-command path (60 KB).
  std::string points;
  for (int i = 0; i < 2000; ++i)
  {
    points += std::to_string(i) + "," + std::to_string(i % 13) + ".5 ";
  }
  Strokes strokes;
  ASSERT_EQ(ParseStrokeSvg(Plain("<polyline points=\"" + points + "\"/>"), strokes), "");
  ASSERT_EQ(strokes[0].size(), 2000u);
  EXPECT_EQ(strokes[0][1999], Eigen::Vector3d(1999, -(1999 % 13 + 0.5), 0));
  std::string d = "M 0,0";
  for (int i = 1; i <= 5000; ++i)
  {
    d += " L " + std::to_string(i) + "," + std::to_string(i % 7);
  }
  ASSERT_EQ(ParseStrokeSvg(Plain("<path d=\"" + d + "\"/>"), strokes), "");
  ASSERT_EQ(strokes[0].size(), 5001u);
  EXPECT_EQ(strokes[0][4321], Eigen::Vector3d(4321, -(4321 % 7), 0));
  std::string relative = "m 0,0";
  for (int i = 0; i < 5000; ++i)
  {
    relative += " l 1,0";
  }
  ASSERT_EQ(ParseStrokeSvg(Plain("<path d=\"" + relative + "\"/>"), strokes), "");
  EXPECT_EQ(strokes[0].back(), Eigen::Vector3d(5000, -0.0, 0));
}

TEST(StrokeFiles, HostileSvgIsRefused)
{
  std::string points;
  for (int i = 0; i < 2000; ++i)
  {
    points += std::to_string(i) + "," + std::to_string(i) + " ";
  }
  const std::string whole = Plain("<polyline points=\"" + points + "\"/>");
  ExpectRefused(whole.substr(0, whole.size() / 2), "not well-formed XML"); // cut inside the points attribute
  ExpectRefused(whole.substr(0, whole.size() - 6), "not well-formed XML"); // </svg> missing
  ExpectRefused(Plain("<path d=\"M 0 0 L 1 1\"/>").insert(20, 1, '\0'), "NUL byte");
  std::string junk;
  for (int i = 0; i < 100000; ++i)
  {
    junk += static_cast<char>(1u + (static_cast<unsigned>(i) * 7919u) % 255u);
  }
  ExpectRefused(junk, "StrokeFile");
  std::string deep;
  for (int i = 0; i < 100000; ++i)
    deep += "<g>";
  deep += "<path d=\"M 0 0 L 1 1\"/>";
  for (int i = 0; i < 100000; ++i)
    deep += "</g>";
  ExpectRefused(Plain(deep), "nested deeper than 256");
  ExpectRefused(Plain("<path d=\"M 0 0 L 1 " + std::string(10000000, '7') + "\"/>"), "more than 512 characters");
  ExpectRefused(Plain("<path d=\"M 0 0 L 1 1e999\"/>"), "beyond the range of a double");
  ExpectRefused(Plain("<path d=\"M 0 0 L 1 1\" transform=\"scale(1e300)\"/><path d=\"M 1e300 0 L 0 0\""
                      " transform=\"scale(1e300)\"/>"),
    "overflows a double");
  // Curves so large that each is cut into the most chords: the point budget refuses the file.
  std::string huge = "M 0 0";
  for (int i = 0; i < 5000; ++i)
  {
    huge += " C 1e9 1e9 -1e9 1e9 0 0";
  }
  ExpectRefused(Plain("<path d=\"" + huge + "\"/>"), "more points than are read from a file of this size");
  EXPECT_EQ(StrokePointBudget(0), kStrokePointsFloor);
  EXPECT_EQ(StrokePointBudget(1000), kStrokePointsFloor + 4000);
  EXPECT_EQ(StrokePointBudget(std::size_t(1) << 40), kMaxStrokeFilePoints);
  // Underflow is harmless: 1e-400 reads as 0.
  Strokes strokes;
  ASSERT_EQ(ParseStrokeSvg(Plain("<path d=\"M 1e-400 0 L 1 1\"/>"), strokes), "");
  EXPECT_EQ(strokes[0][0].x(), 0.0);
}

TEST(StrokeFiles, HostileCsvIsRefused)
{
  Strokes strokes;
  const auto refused = [&](const std::string& text, const std::string& words) {
    const std::string error = ParseStrokeCsv(text, strokes);
    EXPECT_NE(error.find(words), std::string::npos) << error;
    EXPECT_TRUE(strokes.empty());
  };
  refused("id,x,y\n1,0,0\n1," + std::string(100000, '1') + ",2\n", "line 3: longer than 65536");
  refused("id,x,y\n1,0,0\n1,1" + std::string(1, '\0') + "5,2\n", "line 3: holds a NUL byte");
  refused("1,0,0\n1,1e999,0\n", "line 2: x is a number beyond the range");
  refused("1,0,0\n1,1," + std::string(600, '3') + "\n", "line 2: y is a number of more than 512");
  refused("1,0,0\n1,abc,2\n", "line 2: x and y must be numbers");
  refused("1,0\n", "line 1: has fewer than 3 fields");
  // The reader's own conventions stay: ';' and tabs separate, quotes and spaces are dropped (an unterminated quote
  // too), '#' lines, blank lines and a header are skipped.
  ASSERT_EQ(ParseStrokeCsv("# traced\n\"id\";\"x\";\"y\"\n\n a ;\"1.5\";2\r\nb\t3\t4\n\"a,5,6\n", strokes), "");
  ASSERT_EQ(strokes.size(), 2u);
  EXPECT_EQ(strokes[0], (std::vector<Eigen::Vector3d>{ { 1.5, 2, 0 }, { 5, 6, 0 } }));
  EXPECT_EQ(strokes[1], (std::vector<Eigen::Vector3d>{ { 3, 4, 0 } }));
}
