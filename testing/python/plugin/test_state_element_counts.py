# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: a state file with a wrong element count keeps its pipeline and says which property is wrong.

A fixed-size property given another number of values in a state file (LeafFitFilter's BasePoint with one value,
VirtualScanner's LookAt with two) used to make ParaView call the set method with the wrong arguments: "could not
find requested method ... Aborting execution", and the rest of the proxy's state, its Input among it, was lost (the
loaded filter had no input). With the counted-property helper (vtkSICountedDoubleVectorProperty) the values are
not pushed: every connection of the loaded pipeline is kept; LeafFitFilter refuses to run with an error naming
BasePoint and the count (empty outputs), and the scanner's LookAt keeps its previous value with an error naming it
at load time. Correcting the property (its count first: the proxy holds the state's count) makes the fit run.

    pvpython test_state_element_counts.py --plugin PlantMorph.so --work DIR
"""
import os
import re

from plantmorph_testing import Checks, Messages, load_plugin, parse_arguments

arguments = parse_arguments()

from paraview.simple import *  # noqa: F401,F403
from paraview import servermanager
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

load_plugin(arguments.plugin, globals())
checks = Checks()

SetActiveSource(None)
leaf = LeafOutlineSource()
scanner = VirtualScanner(Input=leaf, ScannerType="Depth camera", Resolution=[60, 40], LookAt=[0, 0, 0.5])
fit = LeafFitFilter(Input=scanner, UseBasePoint=1)
after = Calculator(Input=fit)
good = os.path.join(arguments.work, "state_element_counts_good.pvsm")
bad = os.path.join(arguments.work, "state_element_counts_bad.pvsm")
SaveState(good)


def shorten(text, name, keep):
    """The state's property `name` with only its first `keep` elements."""
    i = text.index('name="%s"' % name)
    start = text.rindex("<Property", 0, i)
    end = text.index("</Property>", i) + len("</Property>")
    prop = re.sub(r'number_of_elements="\d+"', 'number_of_elements="%d"' % keep, text[start:end])
    prop = re.sub(r'\s*<Element index="(\d+)"[^>]*/>',
                  lambda m: m.group(0) if int(m.group(1)) < keep else "", prop)
    return text[:start] + prop + text[end:]


with open(good) as f:
    text = f.read()
with open(bad, "w") as f:
    f.write(shorten(shorten(text, "BasePoint", 1), "LookAt", 2))

ResetSession()
load_plugin(arguments.plugin, globals())
said = vtkStringOutputWindow()
previous = vtkOutputWindow.GetInstance()
vtkOutputWindow.SetInstance(said)
LoadState(bad)
vtkOutputWindow.SetInstance(previous)
log = said.GetOutput()
checks.check("could not find requested method" not in log and "Aborting" not in log,
             "loading: no interpreter abort %s" % log[-1500:])
checks.check("LookAt: 2 numbers, 3 expected" in log, "loading: an error naming LookAt and the count %s" % log[-1500:])

sources = {p.GetXMLName(): p for p in GetSources().values()}


def input_of(name):
    prop = sources[name].GetProperty("Input")
    return [prop.GetProxy(k).GetXMLName() for k in range(prop.GetNumberOfProxies())]


checks.check(sorted(sources) == ["Calculator", "LeafFitFilter", "LeafOutlineSource", "VirtualScanner"],
             "every proxy is loaded %s" % sorted(sources))
if len(sources) == 4:
    checks.check(input_of("VirtualScanner") == ["LeafOutlineSource"], "the scanner keeps its input")
    checks.check(input_of("LeafFitFilter") == ["VirtualScanner"], "the fit keeps its input (was lost)")
    checks.check(input_of("Calculator") == ["LeafFitFilter"], "the calculator keeps its input")
    scanned = sources["VirtualScanner"]
    with Messages(scanned) as messages:
        scanned.UpdatePipeline()
        cloud = servermanager.Fetch(scanned)
    checks.check(not messages.errors and cloud.GetNumberOfPoints() > 0,
                 "the scanner runs with LookAt's previous value %s" % messages.errors)
    fit = sources["LeafFitFilter"]
    with Messages(fit) as messages:
        fit.UpdatePipeline()
        blade = servermanager.Fetch(fit)
    checks.check(messages.said("BasePoint = 1 numbers", "3 numbers (x, y, z)", kind="error"),
                 "the fit refuses to run, naming BasePoint and the count %s" % messages.errors)
    checks.check(blade.GetNumberOfPoints() == 0, "... with empty outputs")
    # The proxy holds the state's one number: a script sets the count back first (docs/using-plantmorph.md).
    fit.GetProperty("BasePoint").SetNumberOfElements(3)
    fit.BasePoint = [0, 0, 0]
    with Messages(fit) as messages:
        fit.UpdatePipeline()
        blade = servermanager.Fetch(fit)
    checks.check(not messages.errors and blade.GetNumberOfPoints() > 0,
                 "BasePoint set again: the fit runs %s" % messages.errors)
checks.finish()
