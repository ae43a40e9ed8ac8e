# SPDX-License-Identifier: GPL-3.0-or-later
"""ParaView macro for the tracing GUI test: the view a user sets before tracing (the 2-D interaction mode, looking
from +Z at the photograph), with the exact parallel camera $PLANTMORPH_TRACING_VIEW = "x,y,half height" that
run_tracing_test.py computed its clicks for. Run again after each new Poly Line's first Apply, which may reset the
camera."""
import os

from paraview.simple import GetActiveViewOrCreate, Render

x, y, half_height = (float(v) for v in os.environ["PLANTMORPH_TRACING_VIEW"].split(","))
view = GetActiveViewOrCreate("RenderView")
view.InteractionMode = "2D"
view.CameraPosition = [x, y, 50.0]
view.CameraFocalPoint = [x, y, 0.0]
view.CameraViewUp = [0.0, 1.0, 0.0]
view.CameraParallelScale = half_height
view.CameraParallelProjection = 1
Render(view)
