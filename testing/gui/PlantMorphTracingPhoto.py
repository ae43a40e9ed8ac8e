# SPDX-License-Identifier: GPL-3.0-or-later
"""ParaView macro for the tracing GUI test (testing/gui/run_tracing_test.py): step 2 of docs/tracing-a-tree-photo.md.
Opens the photograph ($PLANTMORPH_TRACING_PHOTO, what File > Open does), scales it to centimetres with a Transform
(0.05 cm per pixel, the trunk's foot at the origin), and shows it coloured by its PNGImage array."""
import os

from paraview.simple import ColorBy, GetActiveViewOrCreate, PNGSeriesReader, SetActiveSource, Show, Transform

photo = PNGSeriesReader(registrationName="tree_photo.png", FileNames=[os.environ["PLANTMORPH_TRACING_PHOTO"]])
in_cm = Transform(registrationName="PhotoInCm", Input=photo)
in_cm.Transform.Scale = [0.05, 0.05, 1.0]
in_cm.Transform.Translate = [-8.0, -1.5, -0.01]  # pixel (160, 30) to the origin, just behind the strokes
display = Show(in_cm, GetActiveViewOrCreate("RenderView"))
ColorBy(display, ("POINTS", "PNGImage"))
SetActiveSource(None)
