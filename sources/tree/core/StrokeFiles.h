// SPDX-License-Identifier: GPL-3.0-or-later
// Stroke files for TreeFromSketchSource's StrokeFile (docs/methods/tree-from-sketch.md, input port 0 "Strokes"). Plain C++17 (Eigen, pugixml),
// no VTK: the fuzzers in testing/fuzz/ link this file pair alone.
//
// Every reader here is linear in the file's size, bounds what one line or token may hold and refuses hostile input
// (binary junk, NUL bytes, unterminated elements, numbers of thousands of digits or beyond a double's range, too
// deep nesting, more points than StrokePointBudget) with an error naming the property, the line or element and the
// accepted range. On error the strokes are empty.
//
// CSV: rows "stroke_id, x, y" (';' or tab also separate fields; a field's surrounding spaces and double quotes are
// dropped); blank lines and lines starting with '#' are skipped, and so are non-numeric lines before the first data
// row (a header). Strokes come in order of their id's first appearance, points in row order. A line holds at most
// kMaxStrokeLineLength characters.
//
// SVG (parsed by pugixml, a real XML parser): each <path>, <polyline>, <polygon> and <line> is a stroke, in document
// order, and every subpath of a path (each M/m) a stroke of its own; Z/z closes a subpath by repeating its first
// point (a polygon likewise), and drawing after Z continues the same stroke from that point. Elements inside <defs>,
// <symbol>, <clipPath>, <mask>, <marker> and <pattern> are not drawn, so they give no stroke; <use>, <rect>, <circle>
// and <ellipse> give none either. Path data follows SVG 1.1's grammar: M L H V C S Q T A Z, absolute and relative,
// implicit repetition (numbers after M/m are L/l), numbers glued as "1-2.5.5" and arc flags as "a1 1 0 01 5 5".
// Path data the grammar refuses is an error naming the element (browsers draw up to the fault; here nothing is
// half read).
// Curves (C S Q T A) are flattened: each is split into n equal parameter steps with n the smallest integer for which
// the bound (step^2 / 8) * max|curve''| on the distance between the curve and its chord polyline is at most
// kSvgCurveTolerance in output units (at most kMaxCurveSegments steps); the points are exact curve points, the end
// point exactly the command's. `transform` on the element and every enclosing group (matrix, translate, scale,
// rotate, skewX, skewY, lists of them) applies. The outermost <svg>'s viewBox maps user units onto its width and
// height (px, mm, cm, in, pt, pc; a missing, percent or em size takes the viewBox's) with preserveAspectRatio
// (default xMidYMid meet), so output units are CSS pixels (1/96 in) of the drawing's page; without a viewBox
// they are the file's user units (as before). A nested <svg> is a viewport as SVG draws it: its x, y translate and
// its own viewBox maps onto its width and height (a missing or percent size takes its viewBox's). An arc whose
// radii are so large that their products overflow a double (about 1e77 and more) is the straight line it is drawn
// as. y is flipped (SVG's y axis points down).
#pragma once

#include <Eigen/Core>

#include <cstddef>
#include <string>
#include <vector>

namespace plantmorph
{

/// Largest distance between a curve and its flattened polyline, in output units (CSS px).
constexpr double kSvgCurveTolerance = 0.1;
/// Most chords one curve command (C S Q T A) is flattened into.
constexpr int kMaxCurveSegments = 1024;
/// Most points all strokes of one file may hold together: kStrokePointsFloor + kStrokePointsPerByte * (file size),
/// at most kMaxStrokeFilePoints. Flattening makes up to kMaxCurveSegments points of one curve command of a few bytes;
/// this bound keeps the work per megabyte of hostile curves (about a second) in proportion to the file.
constexpr std::size_t kMaxStrokeFilePoints = 4000000;
constexpr std::size_t kStrokePointsFloor = 100000;
constexpr std::size_t kStrokePointsPerByte = 4;
/// The point budget of a file of `bytes` bytes (see above).
std::size_t StrokePointBudget(std::size_t bytes);
/// Most characters of one CSV line.
constexpr std::size_t kMaxStrokeLineLength = 65536;
/// Deepest element nesting read in an SVG file (the root is level 1).
constexpr int kMaxSvgDepth = 256;
/// Largest stroke file read, in bytes.
constexpr std::size_t kMaxStrokeFileBytes = std::size_t(512) << 20;

/// Strokes from CSV text (see above). Returns an empty string or a message with the line at fault. `origins`
/// (optional) gets where each stroke comes from: "stroke_id '7' from line 2".
std::string ParseStrokeCsv(const std::string& text, std::vector<std::vector<Eigen::Vector3d>>& strokes,
  std::vector<std::string>* origins = nullptr);
/// Strokes from SVG text (see above). Returns an empty string or a message with the element or position at fault.
/// `origins` (optional): "the SVG element <path id="a"> (line 12)" and ", subpath 2" for a path's later subpaths.
std::string ParseStrokeSvg(const std::string& text, std::vector<std::vector<Eigen::Vector3d>>& strokes,
  std::vector<std::string>* origins = nullptr);
/// Reads a .svg file, or a .csv or .txt file as CSV (by extension, case-insensitive), with the parsers above.
std::string ReadStrokeFile(const std::string& path, std::vector<std::vector<Eigen::Vector3d>>& strokes,
  std::vector<std::string>* origins = nullptr);
/// An error of AddStrokes about strokes read from the file `path` ("Strokes input, stroke N: ..."), said of the
/// file: "StrokeFile 'path', stroke N (stroke_id '7' from line 2): ...". Other errors are returned unchanged.
std::string StrokeFileError(const std::string& error, const std::string& path, const std::vector<std::string>& origins);

} // namespace plantmorph
