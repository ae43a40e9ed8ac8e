// SPDX-License-Identifier: GPL-3.0-or-later
// Disjoint sets over the indices 0..n-1 (union-find with path halving), as every method uses them to join points,
// cubes, graph nodes or parts into connected components. Joining links the higher root under the lower, so a set's
// root is always its lowest member: components numbered by their roots come out in the order of their first members,
// whatever order the joins came in. Plain C++17, no VTK.
#pragma once

#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

namespace plantmorph
{

template <class Index = int>
class DisjointSets
{
public:
  explicit DisjointSets(std::size_t n)
    : Up(n)
  {
    std::iota(this->Up.begin(), this->Up.end(), Index{ 0 });
  }

  std::size_t Size() const { return this->Up.size(); }

  /// The root (lowest member) of a's set. Threads may call Find and Join at once only on disjoint sets.
  Index Find(Index a)
  {
    while (this->Up[a] != a)
      a = this->Up[a] = this->Up[this->Up[a]];
    return a;
  }

  /// Joins the sets of a and b; false when they were one set already.
  bool Join(Index a, Index b) { return this->JoinRoots(this->Find(a), this->Find(b)); }

  /// Joins two roots (as Find returned them); false when they are the same.
  bool JoinRoots(Index a, Index b)
  {
    if (a == b)
      return false;
    if (b < a)
      std::swap(a, b);
    this->Up[b] = a;
    return true;
  }

  /// Each index's parent link, a root pointing to itself (for callers that flatten or hand the links on).
  std::vector<Index>& Links() { return this->Up; }

private:
  std::vector<Index> Up;
};

} // namespace plantmorph
