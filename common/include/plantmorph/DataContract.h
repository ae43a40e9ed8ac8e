// SPDX-License-Identifier: GPL-3.0-or-later
// The data contract every PlantMorph source and filter shares (spec README, "The data contract between the
// filters"): array names and Region codes. Plain C++, no VTK, so algorithm code and VTK wrappers use the same names.
#pragma once

namespace plantmorph
{

/// Array names. A filter passes through every array it does not own.
namespace arrays
{
inline constexpr const char* LeafUV = "LeafUV";   ///< points, double x2: u in [-0.5, 0.5], v in [0, 1]
inline constexpr const char* TCoords = "TCoords"; ///< points, float x2: paper 003 eq. (6), active tcoords
inline constexpr const char* Region = "Region";   ///< points and cells, int: see Region below
inline constexpr const char* Normals = "Normals"; ///< points, float x3, active normals
inline constexpr const char* VeinOrder = "VeinOrder";
inline constexpr const char* VeinWidth = "VeinWidth";
inline constexpr const char* LeafId = "LeafId"; ///< points and cells, int: one id per leaf over a plant, -1 on no leaf
inline constexpr const char* Organ = "Organ";   ///< points and cells, int: see Organ below
/// points, double: the distance to the plant's nearest wood or petiole point (PlantSegmentationFilter; exact near
/// them, between cubes farther); LeafFitFilter puts a leaf's base where the leaf meets the wood
inline constexpr const char* WoodDistance = "WoodDistance";
/// points, double: the distance a scanner measured to the point (VirtualScanner; a terrestrial scan's range)
inline constexpr const char* Range = "Range";
/// points, int: which scanner position saw the point, 0, 1, ... (VirtualScanner)
inline constexpr const char* ScanPosition = "ScanPosition";
} // namespace arrays

/// Values of the `Region` array.
enum Region : int
{
  RegionBlade = 0,
  RegionMidvein = 1, ///< midvein or another primary vein
  RegionSecondaryVein = 2,
  RegionTertiaryVein = 3, ///< tertiary vein or free-ending veinlet
  RegionMargin = 4,
  RegionPetiole = 5
};

/// Values of the `Organ` array: TreeFromSketchSource's truth, carried by VirtualScanner to every point it scans, and
/// PlantSegmentationFilter's label; LeafFitFilter counts the leaf points on no leaf by it, TreeFitFilter reads wood.
enum Organ : int
{
  OrganWood = 0,
  OrganLeaf = 1,
  OrganPetiole = 2
};

/// Where a leaf meets its wood: its point of the least WoodDistance minus this times its distance from the leaf's
/// centroid (near the wood, and at an end of the leaf: a margin touching other wood, or the twig beyond the base,
/// can be as near the wood). PlantSegmentationFilter's leaves table puts a leaf's Base there, and LeafFitFilter
/// (OrientByWood) moves a guessed base there, so the two agree. On the benchmark's herb and five shrubs, of the 1,208
/// leaves whose base was scanned, the Base within 5 % of the leaf's length of the true one on 633 (the point fewest
/// links from the wood: 498; on a prototype the point nearest the wood alone did worse than that, weights 0.25 and 1
/// about as well).
inline constexpr double LeafBaseCentreWeight = 0.5;

/// The score of a leaf's point as where the leaf meets its wood (the least is the base): its WoodDistance minus
/// LeafBaseCentreWeight times its distance from the leaf's centroid. One rule for both filters.
inline double LeafBaseScore(double woodDistance, double distanceFromCentre)
{
  return woodDistance - LeafBaseCentreWeight * distanceFromCentre;
}

} // namespace plantmorph
