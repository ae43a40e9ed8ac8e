// SPDX-License-Identifier: GPL-3.0-or-later
#include "BladeMesher.h"

#include <plantmorph/DataContract.h>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/property_map.h>
#include <CGAL/spatial_sort.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <sstream>

namespace plantmorph
{
namespace
{
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
struct VertexInfo
{
  int id = -1; ///< index into the outline's points; -1 for Steiner points
};
using VertexBase =
  CGAL::Triangulation_vertex_base_with_info_2<VertexInfo, Kernel, CGAL::Delaunay_mesh_vertex_base_2<Kernel>>;
using FaceBase = CGAL::Delaunay_mesh_face_base_2<Kernel>;
using DataStructure = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
using Triangulation = CGAL::Constrained_Delaunay_triangulation_2<Kernel, DataStructure, CGAL::Exact_predicates_tag>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Triangulation>;
using Mesher = CGAL::Delaunay_mesher_no_edge_refinement_2<Triangulation, Criteria>;
using Point = Kernel::Point_2;
using VertexHandle = Triangulation::Vertex_handle;

std::vector<Point> LoopPoints(const std::vector<Eigen::Vector2d>& points, const std::vector<int>& loop)
{
  std::vector<Point> result;
  result.reserve(loop.size());
  for (int id : loop)
    result.emplace_back(points[id].x(), points[id].y());
  return result;
}

} // namespace

double PolygonArea(const std::vector<Eigen::Vector2d>& points, const std::vector<int>& loop)
{
  double twice = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i)
  {
    const Eigen::Vector2d& a = points[loop[i]];
    const Eigen::Vector2d& b = points[loop[(i + 1) % loop.size()]];
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return 0.5 * twice;
}

std::string ValidateBladeOutline(const BladeOutline& outline)
{
  const std::size_t n = outline.points.size();
  if (outline.uv.size() != n || outline.region.size() != n)
    return "outline: points, LeafUV and Region differ in length";
  if (outline.boundary.size() < 3)
    return "outline: the boundary needs at least 3 distinct points";
  if (outline.midvein.size() < 2)
    return "outline: the midvein needs at least 2 points";
  for (const Eigen::Vector2d& p : outline.points)
  {
    if (!p.allFinite())
      return "outline: a sample is not finite (NaN or infinite coordinates)";
  }
  for (int id : outline.boundary)
  {
    if (id < 0 || static_cast<std::size_t>(id) >= n)
      return "outline: boundary refers to a point that does not exist";
  }
  for (int id : outline.midvein)
  {
    if (id < 0 || static_cast<std::size_t>(id) >= n)
      return "outline: midvein refers to a point that does not exist";
  }

  // The midvein splits the outline into two half blades; each half and the whole must be simple polygons, and both
  // halves counter-clockwise, so the midvein lies inside the blade and crosses no margin.
  const auto startIt = std::find(outline.boundary.begin(), outline.boundary.end(), outline.midvein.front());
  const auto endIt = std::find(outline.boundary.begin(), outline.boundary.end(), outline.midvein.back());
  if (startIt == outline.boundary.end() || endIt == outline.boundary.end() || startIt == endIt)
    return "outline: the midvein must start and end at two different outline points";
  const std::size_t start = static_cast<std::size_t>(startIt - outline.boundary.begin());
  const std::size_t end = static_cast<std::size_t>(endIt - outline.boundary.begin());

  auto isSimple = [&](const std::vector<int>& loop) {
    std::vector<Point> polygon = LoopPoints(outline.points, loop);
    return CGAL::is_simple_2(polygon.begin(), polygon.end(), Kernel());
  };
  if (!isSimple(outline.boundary))
    return "outline: the margin crosses itself (the parameters fold the leaf); choose smaller amplitudes";

  const std::size_t m = outline.boundary.size();
  // Half 1: boundary from the midvein's start to its end (counter-clockwise), then back down the midvein.
  std::vector<int> first, second;
  for (std::size_t i = start; i != end; i = (i + 1) % m)
    first.push_back(outline.boundary[i]);
  first.insert(first.end(), outline.midvein.rbegin(), outline.midvein.rend() - 1);
  // Half 2: up the midvein, then the boundary from its end back to its start.
  second.assign(outline.midvein.begin(), outline.midvein.end() - 1);
  for (std::size_t i = end; i != start; i = (i + 1) % m)
    second.push_back(outline.boundary[i]);
  for (const std::vector<int>* half : { &first, &second })
  {
    if (half->size() < 3 || !isSimple(*half) || PolygonArea(outline.points, *half) <= 0.0)
      return "outline: the midvein leaves the blade or crosses a margin (the parameters fold the leaf)";
  }
  if (PolygonArea(outline.points, outline.boundary) <= 0.0)
    return "outline: the boundary must run counter-clockwise";

  // Further veins: ends on the boundary, everything else strictly inside it.
  const std::vector<Point> polygon = LoopPoints(outline.points, outline.boundary);
  auto strictlyInside = [&](const Eigen::Vector2d& p) {
    return CGAL::bounded_side_2(polygon.begin(), polygon.end(), Point(p.x(), p.y()), Kernel()) == CGAL::ON_BOUNDED_SIDE;
  };
  for (const std::vector<int>& vein : outline.veins)
  {
    if (vein.size() < 2)
      return "outline: a vein needs at least 2 points";
    for (int id : vein)
    {
      if (id < 0 || static_cast<std::size_t>(id) >= n)
        return "outline: a vein refers to a point that does not exist";
    }
    const auto onBoundary = [&](int id) {
      return std::find(outline.boundary.begin(), outline.boundary.end(), id) != outline.boundary.end();
    };
    if (!onBoundary(vein.front()) || !onBoundary(vein.back()) || vein.front() == vein.back())
      return "outline: a vein must start and end at two different outline points";
    for (std::size_t i = 0; i + 1 < vein.size(); ++i)
    {
      if ((i > 0 && !strictlyInside(outline.points[vein[i]])) ||
        !strictlyInside(0.5 * (outline.points[vein[i]] + outline.points[vein[i + 1]])))
        return "outline: a vein leaves the blade";
    }
  }
  return {};
}

std::string MeshBlade(
  const BladeOutline& outline, const BladeMeshParameters& options, const UVSolver& solveUV, BladeMesh& mesh)
{
  mesh = BladeMesh();
  std::string error = ValidateBladeOutline(outline);
  if (!error.empty())
    return error;
  if (options.quality && !(options.maxEdgeLength > 0.0 && std::isfinite(options.maxEdgeLength)))
    return "MeshQuality: the maximum edge length must be a positive number";
  auto keepGoing = [&](double fraction) { return !options.progress || options.progress(fraction); };

  // Insert the samples in spatial-sort order with a face hint: in their order along the outline, incremental
  // Delaunay insertion is at its quadratic worst.
  Triangulation cdt;
  std::vector<std::size_t> order(outline.points.size());
  std::vector<Point> points;
  points.reserve(outline.points.size());
  for (std::size_t i = 0; i < outline.points.size(); ++i)
  {
    order[i] = i;
    points.emplace_back(outline.points[i].x(), outline.points[i].y());
  }
  using SortTraits = CGAL::Spatial_sort_traits_adapter_2<Kernel, CGAL::Pointer_property_map<Point>::type>;
  CGAL::spatial_sort(order.begin(), order.end(), SortTraits(CGAL::make_property_map(points)));
  std::vector<VertexHandle> handles(outline.points.size());
  Triangulation::Face_handle hint;
  for (std::size_t i : order)
  {
    handles[i] = cdt.insert(points[i], hint);
    if (handles[i]->info().id >= 0)
      return "outline: two samples coincide";
    handles[i]->info().id = static_cast<int>(i);
    hint = handles[i]->face();
  }
  const std::size_t m = outline.boundary.size();
  for (std::size_t i = 0; i < m; ++i)
    cdt.insert_constraint(handles[outline.boundary[i]], handles[outline.boundary[(i + 1) % m]]);
  for (std::size_t i = 0; i + 1 < outline.midvein.size(); ++i)
    cdt.insert_constraint(handles[outline.midvein[i]], handles[outline.midvein[i + 1]]);
  for (const std::vector<int>& vein : outline.veins)
  {
    for (std::size_t i = 0; i + 1 < vein.size(); ++i)
      cdt.insert_constraint(handles[vein[i]], handles[vein[i + 1]]);
  }
  if (cdt.number_of_vertices() != outline.points.size())
    return "outline: a constraint crossed another (the outline is not simple, or two veins cross)";

  Mesher mesher(cdt, Criteria(options.shapeBound, options.quality ? options.maxEdgeLength : 0.0));
  // CGAL 5.5 leaves the mesher's seeds_mark uninitialised (UBSan: "load of value 32 ... for type 'bool'");
  // clear_seeds() sets it before init() reads it. No seeds: the domain is every bounded face, inside the outline.
  mesher.clear_seeds();
  mesher.init();
  if (options.quality)
  {
    // Expected vertex count of the refined mesh: area / (area per vertex ~ 0.43 h^2), for the progress bar.
    const double area = PolygonArea(outline.points, outline.boundary);
    const double expected = std::max(1.0, area / (0.43 * options.maxEdgeLength * options.maxEdgeLength));
    std::size_t steps = 0;
    while (!mesher.is_refinement_done())
    {
      mesher.step_by_step_refine_mesh();
      if (++steps % 4096 == 0)
      {
        if (cdt.number_of_vertices() > options.maxVertices)
        {
          std::ostringstream message;
          message << "MeshQuality: refinement needs more than " << options.maxVertices
                  << " vertices; lower Resolution or use paper mode";
          return message.str();
        }
        if (!keepGoing(0.8 * std::min(1.0, cdt.number_of_vertices() / expected)))
          return "aborted";
      }
    }
  }

  // Number the vertices: the outline's first (same ids), Steiner points after.
  mesh.points = outline.points;
  mesh.uv = outline.uv;
  mesh.region = outline.region;
  std::vector<VertexHandle> steiner;
  for (auto v = cdt.finite_vertices_begin(); v != cdt.finite_vertices_end(); ++v)
  {
    if (v->info().id < 0)
    {
      v->info().id = static_cast<int>(mesh.points.size());
      mesh.points.emplace_back(v->point().x(), v->point().y());
      mesh.uv.emplace_back(0.0, 0.0);
      mesh.region.push_back(RegionBlade);
      steiner.push_back(v);
    }
  }
  std::vector<char> known(mesh.points.size(), 0);
  std::fill(known.begin(), known.begin() + static_cast<std::ptrdiff_t>(outline.points.size()), 1);

  // The mesher never splits a constraint, so every Steiner point is interior: margin and midvein keep exactly
  // their samples (and their exact LeafUV).
  for (const VertexHandle& v : steiner)
  {
    auto edge = cdt.incident_edges(v), done = edge;
    do
    {
      if (!cdt.is_infinite(edge) && cdt.is_constrained(*edge))
        return "meshing: a refinement point fell on the outline or the midvein";
    } while (++edge != done);
  }

  // Interior Steiner points, breadth first from the outline: each is solved once, when it is reached, with the
  // mean LeafUV of its already-known neighbours as the guess.
  std::vector<char> queued(mesh.points.size(), 0);
  std::deque<VertexHandle> queue;
  auto enqueueUnknownNeighbours = [&](const VertexHandle& v) {
    auto neighbour = cdt.incident_vertices(v), done = neighbour;
    do
    {
      if (!cdt.is_infinite(neighbour))
      {
        const int id = neighbour->info().id;
        if (!known[id] && !queued[id])
        {
          queued[id] = 1;
          queue.push_back(neighbour);
        }
      }
    } while (++neighbour != done);
  };
  for (std::size_t i = 0; i < outline.points.size(); ++i)
    enqueueUnknownNeighbours(handles[i]);
  std::size_t solved = 0;
  while (!queue.empty())
  {
    const VertexHandle v = queue.front();
    queue.pop_front();
    Eigen::Vector2d sum(0.0, 0.0);
    int count = 0;
    auto neighbour = cdt.incident_vertices(v), done = neighbour;
    do
    {
      if (!cdt.is_infinite(neighbour) && known[neighbour->info().id])
      {
        sum += mesh.uv[neighbour->info().id];
        ++count;
      }
    } while (++neighbour != done);
    const int id = v->info().id;
    const Eigen::Vector2d p(v->point().x(), v->point().y());
    const Eigen::Vector2d guess = sum / count; // count >= 1: v was queued by a known neighbour
    mesh.uv[id] = solveUV ? solveUV(p, guess) : guess;
    known[id] = 1;
    ++solved;
    enqueueUnknownNeighbours(v);
  }
  if (solved != steiner.size())
    return "meshing: an interior point is not connected to the outline";

  if (!keepGoing(0.9))
    return "aborted";

  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
  {
    if (f->is_in_domain())
      mesh.triangles.push_back({ f->vertex(0)->info().id, f->vertex(1)->info().id, f->vertex(2)->info().id });
  }
  if (mesh.triangles.empty())
    return "meshing: the outline encloses no area";
  return {};
}

} // namespace plantmorph
