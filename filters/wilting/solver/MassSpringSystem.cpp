// SPDX-License-Identifier: GPL-3.0-or-later
#include "MassSpringSystem.h"

#include "MassSpringThreads.h"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace plantmorph
{

namespace
{
/// VTK hexahedron corner index of the corner with bits (i, j, k).
int HexCorner(int i, int j, int k)
{
  return 4 * k + (j ? (i ? 2 : 3) : (i ? 1 : 0));
}

/// The eight corner Jacobian determinants of a hexahedron at positions x (edges along the +i, +j, +k directions
/// at each corner).
std::array<double, 8> CornerJacobians(const std::array<Eigen::Vector3d, 8>& x)
{
  std::array<double, 8> det{};
  for (int k = 0; k < 2; ++k)
  {
    for (int j = 0; j < 2; ++j)
    {
      for (int i = 0; i < 2; ++i)
      {
        const Eigen::Vector3d ei = x[HexCorner(1, j, k)] - x[HexCorner(0, j, k)];
        const Eigen::Vector3d ej = x[HexCorner(i, 1, k)] - x[HexCorner(i, 0, k)];
        const Eigen::Vector3d ek = x[HexCorner(i, j, 1)] - x[HexCorner(i, j, 0)];
        det[HexCorner(i, j, k)] = ei.dot(ej.cross(ek));
      }
    }
  }
  return det;
}
} // namespace

int MassSpringSystem::AddNode(const Eigen::Vector3d& rest, double mass, bool fixed)
{
  this->Rest.push_back(rest);
  this->NodeMasses.push_back(mass);
  this->Fixed.push_back(fixed ? 1 : 0);
  return static_cast<int>(this->Rest.size() - 1);
}

int MassSpringSystem::AddSpring(int a, int b, double stiffness, double damping)
{
  if (a > b)
  {
    std::swap(a, b);
  }
  const unsigned long long key =
    (static_cast<unsigned long long>(static_cast<unsigned int>(a)) << 32) | static_cast<unsigned int>(b);
  const auto found = this->SpringOfPair.find(key);
  if (found != this->SpringOfPair.end())
  {
    MassSpringSpring& spring = this->SpringList[static_cast<std::size_t>(found->second)];
    spring.stiffness += stiffness;
    spring.damping += damping;
    return found->second;
  }
  MassSpringSpring spring;
  spring.a = a;
  spring.b = b;
  spring.stiffness = stiffness;
  spring.damping = damping;
  if (a >= 0 && b < static_cast<int>(this->Rest.size()))
  {
    spring.restLength = (this->Rest[static_cast<std::size_t>(b)] - this->Rest[static_cast<std::size_t>(a)]).norm();
  }
  this->SpringList.push_back(spring);
  const int index = static_cast<int>(this->SpringList.size() - 1);
  this->SpringOfPair.emplace(key, index);
  return index;
}

std::string MassSpringSystem::Finalize()
{
  const std::size_t n = this->Rest.size();
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!this->Rest[i].allFinite() || !std::isfinite(this->NodeMasses[i]) || this->NodeMasses[i] < 0.0 ||
      (!this->Fixed[i] && !(this->NodeMasses[i] > 0.0)))
    {
      std::ostringstream message;
      message << "mass-spring node " << i << " has a non-finite position or a mass that is not positive ("
              << this->NodeMasses[i] << ")";
      return message.str();
    }
  }
  for (std::size_t e = 0; e < this->SpringList.size(); ++e)
  {
    const MassSpringSpring& s = this->SpringList[e];
    if (s.a < 0 || s.b >= static_cast<int>(n) || s.a == s.b || !(s.restLength > 0.0) || !std::isfinite(s.stiffness) ||
      s.stiffness < 0.0 || !std::isfinite(s.damping) || s.damping < 0.0)
    {
      std::ostringstream message;
      message << "mass-spring spring " << e << " (" << s.a << ", " << s.b
              << ") has bad nodes, a zero rest length or a negative or non-finite stiffness or damping";
      return message.str();
    }
  }
  // Adjacency (CSR), each node's entries in spring order.
  this->AdjacencyOffsets.assign(n + 1, 0);
  for (const MassSpringSpring& s : this->SpringList)
  {
    ++this->AdjacencyOffsets[static_cast<std::size_t>(s.a) + 1];
    ++this->AdjacencyOffsets[static_cast<std::size_t>(s.b) + 1];
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    this->AdjacencyOffsets[i + 1] += this->AdjacencyOffsets[i];
  }
  this->Adjacency.assign(this->AdjacencyOffsets[n], MassSpringNeighbour());
  std::vector<std::size_t> fill(this->AdjacencyOffsets.begin(), this->AdjacencyOffsets.end() - 1);
  for (std::size_t e = 0; e < this->SpringList.size(); ++e)
  {
    const MassSpringSpring& s = this->SpringList[e];
    this->Adjacency[fill[static_cast<std::size_t>(s.a)]++] = { s.b, static_cast<int>(e), -1 };
    this->Adjacency[fill[static_cast<std::size_t>(s.b)]++] = { s.a, static_cast<int>(e), +1 };
  }
  this->RestJacobians.clear();
  for (const std::array<int, 8>& hex : this->HexList)
  {
    std::array<Eigen::Vector3d, 8> x;
    for (int c = 0; c < 8; ++c)
    {
      x[c] = this->Rest[static_cast<std::size_t>(hex[c])];
    }
    const std::array<double, 8> det = CornerJacobians(x);
    this->RestJacobians.insert(this->RestJacobians.end(), det.begin(), det.end());
  }
  this->SpringOfPair.clear();
  return std::string();
}

void MassSpringSystem::EvaluateSprings(
  const double* u, bool clamp, double* force, double* tangent, MassSpringThreads& threads) const
{
  const MassSpringSpring* springs = this->SpringList.data();
  const Eigen::Vector3d* rest = this->Rest.data();
  threads.For(this->SpringList.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e)
    {
      const MassSpringSpring& s = springs[e];
      const double* ua = u + 3 * s.a;
      const double* ub = u + 3 * s.b;
      const Eigen::Vector3d& xa = rest[s.a];
      const Eigen::Vector3d& xb = rest[s.b];
      const double z0 = xb[0] + ub[0] - xa[0] - ua[0];
      const double z1 = xb[1] + ub[1] - xa[1] - ua[1];
      const double z2 = xb[2] + ub[2] - xa[2] - ua[2];
      const double length = std::sqrt(z0 * z0 + z1 * z1 + z2 * z2);
      double* f = force + 3 * e;
      double* d = tangent + 6 * e;
      if (!(length > 0.0))
      {
        f[0] = f[1] = f[2] = 0.0;
        d[0] = d[3] = d[5] = s.stiffness;
        d[1] = d[2] = d[4] = 0.0;
        continue;
      }
      const double inv = 1.0 / length;
      const double n0 = z0 * inv;
      const double n1 = z1 * inv;
      const double n2 = z2 * inv;
      const double magnitude = s.stiffness * (length - s.restLength);
      f[0] = magnitude * n0;
      f[1] = magnitude * n1;
      f[2] = magnitude * n2;
      // D = k [ g I + (1 - g) n n^T ], g = 1 - L/l (clamped at 0 when asked).
      double g = 1.0 - s.restLength * inv;
      if (clamp && g < 0.0)
      {
        g = 0.0;
      }
      const double kg = s.stiffness * g;
      const double kn = s.stiffness * (1.0 - g);
      d[0] = kg + kn * n0 * n0;
      d[1] = kn * n0 * n1;
      d[2] = kn * n0 * n2;
      d[3] = kg + kn * n1 * n1;
      d[4] = kn * n1 * n2;
      d[5] = kg + kn * n2 * n2;
    }
  });
}

void MassSpringSystem::InternalForce(const double* u, double* out) const
{
  std::fill(out, out + 3 * this->Rest.size(), 0.0);
  for (const MassSpringSpring& s : this->SpringList)
  {
    const Eigen::Vector3d z = this->Rest[static_cast<std::size_t>(s.b)] +
      Eigen::Vector3d(u[3 * s.b], u[3 * s.b + 1], u[3 * s.b + 2]) - this->Rest[static_cast<std::size_t>(s.a)] -
      Eigen::Vector3d(u[3 * s.a], u[3 * s.a + 1], u[3 * s.a + 2]);
    const double length = z.norm();
    if (!(length > 0.0))
    {
      continue;
    }
    const Eigen::Vector3d f = s.stiffness * (length - s.restLength) * z / length;
    for (int c = 0; c < 3; ++c)
    {
      out[3 * s.a + c] -= f[c];
      out[3 * s.b + c] += f[c];
    }
  }
}

double MassSpringSystem::SpringLength(const MassSpringSpring& s, const double* u) const
{
  const Eigen::Vector3d z = this->Rest[static_cast<std::size_t>(s.b)] +
    Eigen::Vector3d(u[3 * s.b], u[3 * s.b + 1], u[3 * s.b + 2]) - this->Rest[static_cast<std::size_t>(s.a)] -
    Eigen::Vector3d(u[3 * s.a], u[3 * s.a + 1], u[3 * s.a + 2]);
  return z.norm();
}

double MassSpringSystem::SpringEnergy(const double* u) const
{
  double energy = 0.0;
  for (const MassSpringSpring& s : this->SpringList)
  {
    const double stretch = this->SpringLength(s, u) - s.restLength;
    energy += 0.5 * s.stiffness * stretch * stretch;
  }
  return energy;
}

double MassSpringSystem::KineticEnergy(const double* v) const
{
  double energy = 0.0;
  for (std::size_t i = 0; i < this->Rest.size(); ++i)
  {
    energy +=
      0.5 * this->NodeMasses[i] * (v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
  }
  return energy;
}

double MassSpringSystem::GravityEnergy(const double* u, const Eigen::Vector3d& gravity) const
{
  double energy = 0.0;
  for (std::size_t i = 0; i < this->Rest.size(); ++i)
  {
    const Eigen::Vector3d x = this->Rest[i] + Eigen::Vector3d(u[3 * i], u[3 * i + 1], u[3 * i + 2]);
    energy -= this->NodeMasses[i] * gravity.dot(x);
  }
  return energy;
}

double MassSpringSystem::MinimumRelativeJacobian(const double* u) const
{
  double minimum = std::numeric_limits<double>::infinity();
  for (std::size_t h = 0; h < this->HexList.size(); ++h)
  {
    std::array<Eigen::Vector3d, 8> x;
    for (int c = 0; c < 8; ++c)
    {
      const int node = this->HexList[h][c];
      x[c] =
        this->Rest[static_cast<std::size_t>(node)] + Eigen::Vector3d(u[3 * node], u[3 * node + 1], u[3 * node + 2]);
    }
    const std::array<double, 8> det = CornerJacobians(x);
    for (int c = 0; c < 8; ++c)
    {
      minimum = std::min(minimum, det[c] / this->RestJacobians[8 * h + c]);
    }
  }
  return minimum;
}

} // namespace plantmorph
