// SPDX-License-Identifier: GPL-3.0-or-later
#include "VeinGraph.h"

#include <algorithm>
#include <cmath>

namespace plantmorph
{
namespace
{
double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b)
{
  return a.x() * b.y() - a.y() * b.x();
}
} // namespace

VeinGraph::VeinGraph(const Eigen::Vector2d& lower, const Eigen::Vector2d& upper, double cellSize)
{
  const Eigen::Vector2d extent = (upper - lower).cwiseMax(Eigen::Vector2d(1e-12, 1e-12));
  // At most about 4 million cells: coarser cells for tiny requested sizes rather than a grid larger than memory.
  double size = std::max(cellSize, std::sqrt(extent.x() * extent.y() / 4.0e6));
  if (!(size > 0.0) || !std::isfinite(size))
    size = std::max(extent.x(), extent.y());
  this->CellSize = size;
  this->Lower = lower;
  this->Upper = upper;
  this->Width = std::max(1, static_cast<int>(std::ceil(extent.x() / size)));
  this->Height = std::max(1, static_cast<int>(std::ceil(extent.y() / size)));
  this->CellHead.assign(static_cast<std::size_t>(this->Width) * this->Height, -1);
}

int VeinGraph::AddNode(const Eigen::Vector2d& point)
{
  this->NodeList.push_back(point);
  this->FirstEdge.push_back(-1);
  return static_cast<int>(this->NodeList.size() - 1);
}

int VeinGraph::AddVein(int order)
{
  Vein vein;
  vein.order = order;
  this->VeinList.push_back(vein);
  return static_cast<int>(this->VeinList.size() - 1);
}

int VeinGraph::AddEdge(int a, int b, int vein)
{
  Edge edge;
  edge.a = a;
  edge.b = b;
  edge.vein = vein;
  this->EdgeList.push_back(edge);
  const int id = static_cast<int>(this->EdgeList.size() - 1);
  this->NextEdge.push_back(this->FirstEdge[a]);
  this->NextEdge.push_back(this->FirstEdge[b]);
  this->FirstEdge[a] = id;
  this->FirstEdge[b] = id;
  this->Visit.push_back(0);
  this->Register(id);
  return id;
}

VeinGraph::CellRange VeinGraph::Cells(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double pad) const
{
  auto clampX = [&](double x) {
    return std::clamp(static_cast<int>(std::floor((x - this->Lower.x()) / this->CellSize)), 0, this->Width - 1);
  };
  auto clampY = [&](double y) {
    return std::clamp(static_cast<int>(std::floor((y - this->Lower.y()) / this->CellSize)), 0, this->Height - 1);
  };
  CellRange range;
  range.x0 = clampX(std::min(a.x(), b.x()) - pad);
  range.x1 = clampX(std::max(a.x(), b.x()) + pad);
  range.y0 = clampY(std::min(a.y(), b.y()) - pad);
  range.y1 = clampY(std::max(a.y(), b.y()) + pad);
  return range;
}

void VeinGraph::Register(int edge)
{
  const Edge& e = this->EdgeList[edge];
  const CellRange r = this->Cells(this->NodeList[e.a], this->NodeList[e.b], 0.0);
  for (int y = r.y0; y <= r.y1; ++y)
  {
    for (int x = r.x0; x <= r.x1; ++x)
    {
      const std::size_t cell = static_cast<std::size_t>(y) * this->Width + x;
      this->EntryEdge.push_back(edge);
      this->EntryNext.push_back(this->CellHead[cell]);
      this->CellHead[cell] = static_cast<int>(this->EntryEdge.size() - 1);
    }
  }
}

int VeinGraph::Crossing(const Eigen::Vector2d& p, const Eigen::Vector2d& q, int ignore, double& t,
  Eigen::Vector2d& point, int ignoreToo) const
{
  const Eigen::Vector2d r = q - p;
  const double length = r.norm();
  int best = -1;
  t = 2.0;
  if (!(length > 0.0))
    return best;
  ++this->Stamp;
  const CellRange range = this->Cells(p, q, 0.0);
  for (int y = range.y0; y <= range.y1; ++y)
  {
    for (int x = range.x0; x <= range.x1; ++x)
    {
      for (int entry = this->CellHead[static_cast<std::size_t>(y) * this->Width + x]; entry >= 0;
           entry = this->EntryNext[entry])
      {
        const int id = this->EntryEdge[entry];
        if (this->Visit[id] == this->Stamp)
          continue;
        this->Visit[id] = this->Stamp;
        const Edge& e = this->EdgeList[id];
        if (e.a == ignore || e.b == ignore || e.a == ignoreToo || e.b == ignoreToo)
          continue;
        const Eigen::Vector2d& a = this->NodeList[e.a];
        const Eigen::Vector2d s = this->NodeList[e.b] - a;
        const double denominator = Cross(r, s);
        if (std::abs(denominator) <= 1e-14 * length * s.norm())
          continue; // parallel: no single crossing point
        const double along = Cross(a - p, s) / denominator;
        const double on = Cross(a - p, r) / denominator;
        // Ends count: a segment reaching an edge's end node meets that edge.
        if (along > 1e-12 && along <= 1.0 && on >= -1e-12 && on <= 1.0 + 1e-12 && along < t)
        {
          t = along;
          best = id;
          point = a + std::clamp(on, 0.0, 1.0) * s;
        }
      }
    }
  }
  return best;
}

double VeinGraph::FirstCrossing(int from, const Eigen::Vector2d& to, double snap) const
{
  const Eigen::Vector2d p = this->NodeList[from];
  const Eigen::Vector2d d = to - p;
  const double length = d.norm();
  if (!(length > 0.0))
    return 2.0;
  const Eigen::Vector2d end = to + (snap / length) * d;
  double t;
  Eigen::Vector2d point;
  if (this->Crossing(p, end, from, t, point) < 0)
    return 2.0;
  return t * (length + snap) / length;
}

int VeinGraph::FindEdge(int a, int b) const
{
  for (int e = this->FirstEdge[a]; e >= 0; e = this->NextEdge[2 * e + (this->EdgeList[e].a == a ? 0 : 1)])
  {
    if ((this->EdgeList[e].a == a && this->EdgeList[e].b == b) ||
      (this->EdgeList[e].a == b && this->EdgeList[e].b == a))
      return e;
  }
  return -1;
}

int VeinGraph::SplitEdge(int edge, const Eigen::Vector2d& point)
{
  const int node = this->AddNode(point);
  const int b = this->EdgeList[edge].b;
  // The edge keeps its end a and ends at the new node; a new edge of the same vein goes from the node to b.
  // At b, the new edge takes the old one's place in b's list.
  Edge second = this->EdgeList[edge];
  second.a = node;
  this->EdgeList.push_back(second);
  const int id = static_cast<int>(this->EdgeList.size() - 1);
  this->NextEdge.push_back(-1);                           // slot at its end a (the node), linked below
  this->NextEdge.push_back(this->NextEdge[2 * edge + 1]); // slot at its end b: the old edge's successor there
  this->Visit.push_back(0);
  if (this->FirstEdge[b] == edge)
    this->FirstEdge[b] = id;
  else
  {
    for (int e = this->FirstEdge[b]; e >= 0;)
    {
      const int slot = 2 * e + (this->EdgeList[e].a == b ? 0 : 1);
      if (this->NextEdge[slot] == edge)
      {
        this->NextEdge[slot] = id;
        break;
      }
      e = this->NextEdge[slot];
    }
  }
  this->EdgeList[edge].b = node;
  // The node's list: the old edge (at its end b) and the new one (at its end a).
  this->FirstEdge[node] = edge;
  this->NextEdge[2 * edge + 1] = id;
  this->NextEdge[2 * id] = -1;
  this->Register(id);
  return node;
}

VeinGraph::Step VeinGraph::Grow(int from, const Eigen::Vector2d& to, int vein, double snap)
{
  Step step;
  const Eigen::Vector2d p = this->NodeList[from];
  const Eigen::Vector2d d = to - p;
  const double length = d.norm();
  if (!(length > 0.0))
  {
    step.node = from;
    return step;
  }
  const Eigen::Vector2d end = to + (snap / length) * d;
  double t;
  Eigen::Vector2d crossing;
  const int hit = this->Crossing(p, end, from, t, crossing);
  if (hit < 0)
  {
    step.node = this->AddNode(to);
    this->AddEdge(from, step.node, vein);
    return step;
  }
  step.stopped = true;
  step.hitVein = this->EdgeList[hit].vein;
  // The crossing itself becomes the junction: the new edge keeps its direction (growth junction angles stay
  // exact); only a crossing that coincides with an end of the edge met reuses that node.
  int node = -1;
  for (const int end : { this->EdgeList[hit].a, this->EdgeList[hit].b })
  {
    if (node < 0 && end != from && this->NodeList[end] == crossing)
      node = end;
  }
  if (node < 0)
    node = this->SplitEdge(hit, crossing);
  if (node == from)
  {
    step.node = from;
    return step;
  }
  this->AddEdge(from, node, vein);
  step.node = node;
  return step;
}

VeinGraph::Step VeinGraph::Connect(int from, int to, int vein, double snap)
{
  const Eigen::Vector2d p = this->NodeList[from], q = this->NodeList[to];
  double t;
  Eigen::Vector2d crossing;
  if (from == to || this->Crossing(p, q, from, t, crossing, to) >= 0)
    return this->Grow(from, q, vein, snap);
  this->AddEdge(from, to, vein);
  Step step;
  step.node = to;
  step.stopped = true;
  step.hitVein = -1;
  for (int e = this->FirstEdge[to]; e >= 0; e = this->NextEdge[2 * e + (this->EdgeList[e].a == to ? 0 : 1)])
  {
    if (this->EdgeList[e].vein != vein)
      step.hitVein = this->EdgeList[e].vein;
  }
  return step;
}

std::vector<std::vector<int>> VeinGraph::VeinPaths() const
{
  // Edges grouped by vein (counting sort), then each vein walked along the incidence lists from an end.
  const std::size_t veins = this->VeinList.size();
  std::vector<int> start(veins + 1, 0);
  for (const Edge& e : this->EdgeList)
    ++start[e.vein + 1];
  for (std::size_t v = 0; v < veins; ++v)
    start[v + 1] += start[v];
  std::vector<int> byVein(this->EdgeList.size());
  {
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (std::size_t e = 0; e < this->EdgeList.size(); ++e)
      byVein[fill[this->EdgeList[e].vein]++] = static_cast<int>(e);
  }
  std::vector<std::vector<int>> paths(veins);
  std::vector<char> used(this->EdgeList.size(), 0);  // each edge belongs to one vein: walked once in all
  std::vector<int> degree(this->NodeList.size(), 0); // within the vein being walked; reset after it
  auto nextAt = [&](int e, int node) { return this->NextEdge[2 * e + (this->EdgeList[e].a == node ? 0 : 1)]; };
  for (std::size_t v = 0; v < veins; ++v)
  {
    if (start[v] == start[v + 1])
      continue;
    for (int k = start[v]; k < start[v + 1]; ++k)
    {
      ++degree[this->EdgeList[byVein[k]].a];
      ++degree[this->EdgeList[byVein[k]].b];
    }
    int first = this->EdgeList[byVein[start[v]]].a;
    for (int k = start[v]; k < start[v + 1]; ++k)
    {
      for (const int n : { this->EdgeList[byVein[k]].a, this->EdgeList[byVein[k]].b })
      {
        if (degree[n] == 1 && (degree[first] != 1 || n < first))
          first = n;
      }
    }
    std::vector<int>& path = paths[v];
    path.push_back(first);
    int node = first;
    while (true)
    {
      int taken = -1;
      for (int e = this->FirstEdge[node]; e >= 0; e = nextAt(e, node))
      {
        if (!used[e] && this->EdgeList[e].vein == static_cast<int>(v))
        {
          taken = e;
          break;
        }
      }
      if (taken < 0)
        break;
      used[taken] = 1;
      node = this->EdgeList[taken].a == node ? this->EdgeList[taken].b : this->EdgeList[taken].a;
      path.push_back(node);
    }
    for (int k = start[v]; k < start[v + 1]; ++k)
      degree[this->EdgeList[byVein[k]].a] = degree[this->EdgeList[byVein[k]].b] = 0;
  }
  return paths;
}

std::vector<int> VeinGraph::VeinDegrees() const
{
  std::vector<int> degree(this->NodeList.size(), 0);
  for (const Edge& e : this->EdgeList)
  {
    if (this->VeinList[e.vein].order != VeinOrderMargin)
    {
      ++degree[e.a];
      ++degree[e.b];
    }
  }
  return degree;
}

std::vector<char> VeinGraph::OnMargin() const
{
  std::vector<char> margin(this->NodeList.size(), 0);
  for (const Edge& e : this->EdgeList)
  {
    if (this->VeinList[e.vein].order == VeinOrderMargin)
      margin[e.a] = margin[e.b] = 1;
  }
  return margin;
}

std::vector<VeinGraph::Face> VeinGraph::Faces(bool withNodes) const
{
  // Half-edge 2e goes a -> b, 2e + 1 goes b -> a. Around each node its half-edges out, by angle, in one flat
  // array (CSR: node n's are around[first[n]] .. around[first[n + 1] - 1]).
  const std::size_t nodes = this->NodeList.size();
  auto origin = [&](int h) { return h % 2 == 0 ? this->EdgeList[h / 2].a : this->EdgeList[h / 2].b; };
  auto target = [&](int h) { return h % 2 == 0 ? this->EdgeList[h / 2].b : this->EdgeList[h / 2].a; };
  std::vector<int> first(nodes + 1, 0);
  for (const Edge& e : this->EdgeList)
  {
    if (e.a != e.b)
    {
      ++first[e.a + 1];
      ++first[e.b + 1];
    }
  }
  for (std::size_t n = 0; n < nodes; ++n)
    first[n + 1] += first[n];
  std::vector<int> around(static_cast<std::size_t>(first[nodes]));
  {
    std::vector<int> fill(first.begin(), first.end() - 1);
    for (std::size_t e = 0; e < this->EdgeList.size(); ++e)
    {
      if (this->EdgeList[e].a == this->EdgeList[e].b)
        continue;
      around[fill[this->EdgeList[e].a]++] = static_cast<int>(2 * e);
      around[fill[this->EdgeList[e].b]++] = static_cast<int>(2 * e + 1);
    }
  }
  std::vector<int> position(2 * this->EdgeList.size(), -1);
  std::vector<std::pair<double, int>> sorted;
  for (std::size_t n = 0; n < nodes; ++n)
  {
    sorted.clear();
    for (int k = first[n]; k < first[n + 1]; ++k)
    {
      const Eigen::Vector2d d = this->NodeList[target(around[k])] - this->NodeList[n];
      sorted.emplace_back(std::atan2(d.y(), d.x()), around[k]);
    }
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t k = 0; k < sorted.size(); ++k)
    {
      around[first[n] + static_cast<int>(k)] = sorted[k].second;
      position[sorted[k].second] = static_cast<int>(k);
    }
  }
  // The face to the left of u -> v continues with v -> w, w the neighbour of v just clockwise of u.
  std::vector<char> seen(position.size(), 0);
  std::vector<Face> faces;
  for (std::size_t start = 0; start < position.size(); ++start)
  {
    if (seen[start] || position[start] < 0)
      continue;
    Face face;
    double twice = 0.0;
    int h = static_cast<int>(start);
    while (!seen[h])
    {
      seen[h] = 1;
      if (withNodes)
        face.nodes.push_back(origin(h));
      face.touchesMargin = face.touchesMargin || this->VeinList[this->EdgeList[h / 2].vein].order == VeinOrderMargin;
      const Eigen::Vector2d& a = this->NodeList[origin(h)];
      const Eigen::Vector2d& b = this->NodeList[target(h)];
      twice += a.x() * b.y() - a.y() * b.x();
      const int twin = h ^ 1;
      const int at = target(h);
      const int count = first[at + 1] - first[at];
      h = around[first[at] + (position[twin] + count - 1) % count];
    }
    face.area = 0.5 * twice;
    if (face.area > 0.0)
      faces.push_back(face);
  }
  return faces;
}

std::vector<int> ReticulumOrders(const VeinGraph& graph)
{
  const std::vector<std::vector<int>> paths = graph.VeinPaths();
  const std::size_t veins = graph.Veins().size();
  // The nodes on a primary or secondary.
  std::vector<char> major(graph.Nodes().size(), 0);
  for (std::size_t v = 0; v < veins; ++v)
  {
    const int order = graph.Order(static_cast<int>(v));
    if (order == VeinOrderPrimary || order == VeinOrderSecondary)
    {
      for (int n : paths[v])
        major[n] = 1;
    }
  }
  std::vector<int> orders(veins);
  for (std::size_t v = 0; v < veins; ++v)
  {
    orders[v] = graph.Order(static_cast<int>(v));
    if (orders[v] == VeinOrderTertiary && !paths[v].empty() && !(major[paths[v].front()] && major[paths[v].back()]))
      orders[v] = VeinOrderQuaternary;
  }
  return orders;
}

} // namespace plantmorph
