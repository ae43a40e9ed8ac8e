# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: a state file with a wrong element count keeps its pipeline and says which property is wrong.

A fixed-size property given another number of values in a state file (LeafFitFilter's BasePoint with one value,
VirtualScanner's LookAt with two) used to make ParaView call the set method with the wrong arguments: "could not
find requested method ... Aborting execution", and the rest of the proxy's state, its Input among it, was lost (the
loaded filter had no input). With the counted-property helper (vtkSICountedDoubleVectorProperty) the values are
not pushed: every connection of the loaded pipeline is kept; LeafFitFilter refuses to run with an error naming
BasePoint and the count (empty outputs), and the scanner's LookAt keeps its previous value with an error naming it
at load time. Integer properties alike (vtkSICountedIntVectorProperty): the scanner's Resolution with one value and
its Seed and the leaf's Lobes with two are errors naming them at load, and the pipeline still runs. Correcting the
property (its count first: the proxy holds the state's count) makes the fit run. Every Int and Double property of
every proxy in xml/ has one of the two helpers (not information-only ones), so no property can bring the abort back.

    pvpython test_state_element_counts.py --plugin PlantMorph.so --work DIR
"""
import glob
import os
import re
import xml.etree.ElementTree as ElementTree

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


def shorten(text, name, keep, proxy=None):
    """The state's property `name` (of the proxy of type `proxy`, else the first) with only its first `keep`
    elements."""
    i = text.index('name="%s"' % name, text.index('type="%s"' % proxy) if proxy else 0)
    start = text.rindex("<Property", 0, i)
    end = text.index("</Property>", i) + len("</Property>")
    prop = re.sub(r'number_of_elements="\d+"', 'number_of_elements="%d"' % keep, text[start:end])
    prop = re.sub(r'\s*<Element index="(\d+)"[^>]*/>',
                  lambda m: m.group(0) if int(m.group(1)) < keep else "", prop)
    return text[:start] + prop + text[end:]




def lengthen(text, proxy, name):
    """The state's property `name` of the proxy of type `proxy` with one more element (a copy of its first)."""
    i = text.index('name="%s"' % name, text.index('type="%s"' % proxy))
    start = text.rindex("<Property", 0, i)
    end = text.index("</Property>", i) + len("</Property>")
    prop = text[start:end]
    count = int(re.search(r'number_of_elements="(\d+)"', prop).group(1))
    first = re.search(r'<Element index="0"[^>]*/>', prop).group(0)
    prop = prop.replace('number_of_elements="%d"' % count, 'number_of_elements="%d"' % (count + 1), 1)
    prop = prop.replace(first, first + first.replace('index="0"', 'index="%d"' % count), 1)
    return text[:start] + prop + text[end:]


with open(good) as f:
    text = f.read()
text = shorten(shorten(text, "BasePoint", 1), "LookAt", 2)
text = shorten(text, "Resolution", 1, proxy="VirtualScanner")
text = lengthen(lengthen(text, "VirtualScanner", "Seed"), "LeafOutlineSource", "Lobes")
with open(bad, "w") as f:
    f.write(text)

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
for said_here in ("Resolution: 1 numbers, 2 expected", "Seed: 2 numbers, 1 expected", "Lobes: 2 numbers, 1 expected"):
    checks.check(said_here in log, "loading: an integer property's error '%s'" % said_here)

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

# Every numeric property is counted: a new property without the helper would bring the abort back for its proxy.
uncounted = []
for path in sorted(glob.glob(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "xml",
                                          "*.xml"))):
    for element in ElementTree.parse(path).getroot().iter():
        kind = element.tag.replace("VectorProperty", "")
        if kind in ("Int", "Double") and element.get("information_only") != "1" and \
                element.get("si_class") != "vtkSICounted%sVectorProperty" % kind:
            uncounted.append("%s: %s" % (os.path.basename(path), element.get("name")))
checks.check(not uncounted, "every Int/Double property has its counted helper (si_class); without: %s" % uncounted)
checks.finish()
