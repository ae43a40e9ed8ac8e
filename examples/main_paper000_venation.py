# SPDX-License-Identifier: GPL-3.0-or-later
"""Paper 000, sec. 3: venation (VenationFilter) on LeafOutlineSource blades.

- paper000_venation_figures.png: the paper's three figures from the presets: paper mulberry (Fig. 10, pinnate
  brochidodromous, secondaries at 45-70 degrees, reticulate tertiaries), ginkgo (Fig. 11, palmate veins by leaf
  growth, forking dichotomously) and poplar (Fig. 12, semicraspedodromous with reticulate tertiaries and free-ending
  veinlets), veins drawn as tubes of their VeinWidth;
- paper000_venation_patterns.png: the nine venation types of Fig. 3 on one ovate blade;
- paper000_mulberry_embossed.png: the paper mulberry blade with its veins embossed (Fig. 10b's relief), lit from
  the side;
- venation_space_colonization.png: Runions et al. 2005's space colonization on a growing blade: open venation (a
  tree, widths by the pipe model) on an entire, a cordate (cucumber) and a five-lobed blade, and closed venation
  (with loops) on the entire blade;
- venation_wilting_species.png: the presets of the wilting species on their blades: cucumber (palmate to the lobe
  and basal-lobe tips, craspedodromous secondaries off each primary, a hierarchical reticulum), watermelon (palmate,
  one primary per lobe with secondaries into its flanks and one to each sub-lobe tip, on LeafOutlineSource's
  Watermelon blade: paper 002's five lobes, each with two sub-lobes a side), the same venation on the pinnatifid
  watermelon blade (SinusDepth 0.8: sinuses nearly to the base, the middle lobe longest) and a tomato leaflet
  (pinnate semicraspedodromous, on a serrate blade).
Each figure's veins and blade are written as .vtp files.

    xvfb-run -a pvbatch examples/main_paper000_venation.py --plugin build/.../PlantMorph.so --output output/
"""
import os

from plantmorph_example import (caption, save_framed_png, save_png, save_state, save_vtp, show_solid, start,
                                white_view)

arguments = start(__doc__)
from paraview.simple import *  # noqa: E402,F401,F403

BLADE = [0.72, 0.86, 0.45]
VEIN = [0.18, 0.38, 0.08]


def show_leaf(leaf, venation, view, offset, tube_scale=1.0):
    """The blade and its veins as tubes of their width, moved by `offset`."""
    blade = Transform(Input=OutputPort(leaf, 0))
    blade.Transform.Translate = offset + [0.0]
    show_solid(blade, view, BLADE)
    # Tube's "By Absolute Scalar" takes the scalar as the radius: half the vein's width.
    radius = Calculator(Input=OutputPort(venation, 0), ResultArrayName="VeinRadius",
                        Function="VeinWidth * %g" % (0.5 * tube_scale))
    tubes = Tube(Input=radius)
    tubes.Scalars = ["POINTS", "VeinRadius"]
    tubes.VaryRadius = "By Absolute Scalar"
    tubes.NumberofSides = 6
    placed = Transform(Input=tubes)
    placed.Transform.Translate = offset + [0.02]
    show_solid(placed, view, VEIN)


# The paper's figures.
view = white_view(1800, 800)
figures = [("mulberry", dict(Preset="Entire", Length=9.0), "Paper mulberry (paper 000 Fig. 10)", "Paper mulberry, Fig. 10"),
           ("ginkgo", dict(Preset="Ginkgo", Length=5.0), "Ginkgo (paper 000 Fig. 11)", "Ginkgo, Fig. 11"),
           ("poplar", dict(Preset="Acute base, acute apex", Length=9.0), "Poplar (paper 000 Fig. 12)", "Poplar, Fig. 12")]
for k, (name, shape, preset, title) in enumerate(figures):
    leaf = LeafOutlineSource(Resolution=100, MeshQuality="Quality", **shape)
    venation = VenationFilter(Input=OutputPort(leaf, 0), Preset=preset, Seed=1)
    save_vtp(venation, os.path.join(arguments.output, "paper000_%s_veins.vtp" % name), port=0)
    save_vtp(leaf, os.path.join(arguments.output, "paper000_%s_blade.vtp" % name), port=0)
    offset = [k * 10.0, 0.0]
    show_leaf(leaf, venation, view, offset)
    caption(view, title, [offset[0] - 2.5, -1.2, 0.0], 0.4)
save_png(view, os.path.join(arguments.output, "paper000_venation_figures.png"))

# Fig. 3: the nine types on one blade.
view = white_view(1500, 1600)
leaf = LeafOutlineSource(Preset="Entire", Length=5.0, Resolution=80, MeshQuality="Quality")
PATTERNS = ["Craspedodromous", "Semicraspedodromous", "Brochidodromous", "Eucamptodromous", "Reticulodromous",
            "Cladodromous", "Arcuate (acrodromous)", "Parallel", "Palmate (actinodromous)"]
for k, pattern in enumerate(PATTERNS):
    venation = VenationFilter(Input=OutputPort(leaf, 0), Preset="Custom", Pattern=pattern, Seed=2,
                              Tertiary=int(pattern not in ("Parallel", "Palmate (actinodromous)")))
    offset = [(k % 3) * 4.5, -(k // 3) * 6.8]
    show_leaf(leaf, venation, view, offset, tube_scale=0.8)
    caption(view, pattern.split(" ")[0], [offset[0] - 1.6, offset[1] - 0.8, 0.0], 0.25)
save_png(view, os.path.join(arguments.output, "paper000_venation_patterns.png"))

# Fig. 10b: relief. A fine blade raised over its veins, seen at an angle with a side light.
view = white_view(1000, 900)
fine = LeafOutlineSource(Preset="Entire", Length=5.0, Resolution=300, MeshQuality="Quality")
embossed = VenationFilter(Input=OutputPort(fine, 0), Preset="Paper mulberry (paper 000 Fig. 10)", Seed=1,
                          EmbossDepth=0.06)
normals = GenerateSurfaceNormals(Input=OutputPort(embossed, 1))
save_vtp(embossed, os.path.join(arguments.output, "paper000_mulberry_embossed.vtp"), port=1)
show_solid(normals, view, BLADE, Specular=0.2)
view.CameraPosition = [4.0, -4.0, 6.0]
view.CameraFocalPoint = [0.0, 2.5, 0.0]
view.CameraViewUp = [0.0, 0.0, 1.0]
save_png(view, os.path.join(arguments.output, "paper000_mulberry_embossed.png"), top_down=False)

# Space colonization (Runions et al. 2005): open venation on three blades, closed venation on the first.
view = white_view(1800, 420)
blades = [("entire", LeafOutlineSource(Preset="Entire", Length=5.0, Resolution=80, MeshQuality="Quality")),
          ("cucumber", LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", BladeLength=5.0, BladeWidth=5.5,
                                         Resolution=80, MeshQuality="Quality")),
          ("five lobes", LeafOutlineSource(Model="Space curve", SpaceCurvePreset="Paper 002 Fig. 8, 5 lobes",
                                           Length=5.0, Resolution=80, MeshQuality="Quality"))]
colonized = [(name, leaf, 0) for name, leaf in blades] + [("entire, closed", blades[0][1], 1)]
for k, ((name, leaf, closed), x) in enumerate(zip(colonized, [0.0, 6.0, 14.0, 22.0])):
    venation = VenationFilter(Input=OutputPort(leaf, 0), Preset="Custom", Pattern="Space colonization (Runions 2005)",
                              ClosedVenation=closed, PrimaryWidth=0.02, Seed=1)
    save_vtp(venation, os.path.join(arguments.output, "venation_colonization_%s_veins.vtp" % name.replace(", ", "_")
                                    .replace(" ", "_")), port=0)
    offset = [x, 0.0]
    show_leaf(leaf, venation, view, offset)
    caption(view, ("Closed, " if closed else "Open, ") + name.split(",")[0], [offset[0] - 1.6, -1.3, 0.0], 0.3)
save_framed_png(view, os.path.join(arguments.output, "venation_space_colonization.png"), [11.0, 2.2, 0.0],
                [11.0, 2.2, 50.0], [0.0, 1.0, 0.0], 3.9)

# The wilting species' presets on their blades; the watermelon twice: the sub-lobed union of paper 002's five lobes
# (shallow sinuses) and the pinnatifid outline (SinusDepth: sinuses nearly to the base, the middle lobe longest).
view = white_view(1900, 560)
species = [("Cucumber (palmate)", LeafOutlineSource(Model="B-spline", BSplinePreset="Cucumber", BladeLength=5.0,
                                                    BladeWidth=5.5, Resolution=80, MeshQuality="Quality"), "Cucumber"),
           ("Watermelon (palmate, lobed)", LeafOutlineSource(Model="Space curve",
                                                             SpaceCurvePreset="Watermelon (5 lobes, sub-lobed)",
                                                             Length=5.0,
                                                             Resolution=80, MeshQuality="Quality"), "Watermelon"),
           ("Watermelon (palmate, lobed)", LeafOutlineSource(Model="Space curve",
                                                             SpaceCurvePreset="Watermelon, pinnatifid (deep sinuses)",
                                                             Resolution=80, MeshQuality="Quality"),
            "Watermelon pinnatifid"),
           ("Tomato (pinnate leaflet)", LeafOutlineSource(Preset="Serrate", Length=5.0, Resolution=80,
                                                          MeshQuality="Quality"), "Tomato leaflet")]
for k, ((preset, leaf, title), x) in enumerate(zip(species, [0.0, 9.0, 17.5, 24.5])):
    venation = VenationFilter(Input=OutputPort(leaf, 0), Preset=preset, Seed=1)
    save_vtp(venation, os.path.join(arguments.output, "venation_%s_veins.vtp" % "_".join(
        title.split(" ")[:2 if "pinnatifid" in title else 1]).lower()), port=0)
    offset = [x, 0.0]
    show_leaf(leaf, venation, view, offset)
    caption(view, title, [offset[0] - 1.6, -1.5, 0.0], 0.3)
save_framed_png(view, os.path.join(arguments.output, "venation_wilting_species.png"), [12.2, 1.9, 0.0],
                [12.2, 1.9, 50.0], [0.0, 1.0, 0.0], 4.45)
save_state(arguments, "paper000_venation")
