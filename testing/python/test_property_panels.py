"""Every PlantMorph proxy gives a tidy Properties panel (plain python3 over the server-manager XML):

- it is in the PlantMorph menu (Sources or Filters), or, for a reader, opens its files from File > Open;
- its label (the menu entry) is spaced words, "Leaf Outline Source", not "LeafOutlineSource";
- the proxy and every property it shows have documentation: ParaView shows it as the panel's tooltips and help;
  a property's is a tooltip, at most 400 characters (the long explanation is in the proxy's, on the help page);
- a proxy with more than 8 properties puts them in groups (the panel's sections) and hides some as advanced (the
  gear button shows them), so the default panel shows what most users change;
- every numeric property a user types has a range domain (the panel then rejects or clamps nonsense);
- a property of several numbers in a row (not a repeatable list) labels each box (ShowComponentLabels).

    python3 test_property_panels.py --xml-dir leaf/vtk tree/vtk ...
"""
import argparse
import os
import re
import sys
import xml.etree.ElementTree as ElementTree

parser = argparse.ArgumentParser()
parser.add_argument("--xml-dir", required=True, nargs="+", help="the folders holding the proxy XML")
arguments = parser.parse_args()

failures = []
proxies = 0
for name, path in sorted((n, os.path.join(d, n)) for d in arguments.xml_dir for n in os.listdir(d)):
    if not name.endswith(".xml"):
        continue
    root = ElementTree.parse(path).getroot()
    for proxy in root.iter("SourceProxy"):
        proxies += 1
        label = "%s (%s)" % (proxy.get("name"), name)
        hints = proxy.find("Hints")
        in_menu = hints is not None and any(h.get("category") == "PlantMorph" for h in hints.iter("ShowInMenu"))
        reader = hints is not None and hints.find("ReaderFactory") is not None
        if not (in_menu or reader):
            failures.append("%s: neither in the PlantMorph menu nor a reader" % label)
        if not proxy.get("label") or re.search(r"[a-z][A-Z]", proxy.get("label")):
            failures.append("%s: label %r is not spaced words (the menu shows it)" % (label, proxy.get("label")))
        documentation = proxy.find("Documentation")
        if documentation is None or not "".join(documentation.itertext()).strip():
            failures.append("%s: no documentation" % label)
        shown = [p for p in proxy if p.tag.endswith("Property") and p.get("information_only") != "1"
                 and p.get("panel_visibility") != "never"]
        for prop in shown:
            text = prop.find("Documentation")
            if text is None or not "".join(text.itertext()).strip():
                failures.append("%s: property %s has no documentation (no tooltip)" % (label, prop.get("name")))
            elif len(" ".join("".join(text.itertext()).split())) > 400:
                failures.append("%s: property %s has a %d-character tooltip (at most 400: a sentence or two; the "
                                "explanation goes in the proxy's documentation, the help page)" % (
                                    label, prop.get("name"), len(" ".join("".join(text.itertext()).split()))))
            # Lists of ids or table rows (repeat_command) have no range: their filter checks each entry.
            typed = (prop.tag in ("IntVectorProperty", "DoubleVectorProperty") and prop.find("Hints") is None
                     and prop.get("repeat_command") != "1")
            domains = [d.tag for d in prop if d.tag.endswith("Domain")]
            if typed and not domains:
                failures.append("%s: numeric property %s has no domain (range, enumeration or boolean)" % (
                    label, prop.get("name")))
            # A row of several numbers (not a repeatable list) shows one box per number: each needs a label.
            several = (prop.tag in ("IntVectorProperty", "DoubleVectorProperty") and prop.get("repeat_command") != "1"
                       and int(prop.get("number_of_elements") or 1) > 1)
            if several and prop.find("Hints/ShowComponentLabels") is None:
                failures.append("%s: property %s shows %s unlabelled boxes (add ShowComponentLabels)" % (
                    label, prop.get("name"), prop.get("number_of_elements")))
        if len(shown) > 8:
            if not proxy.findall("PropertyGroup"):
                failures.append("%s: %d properties and no PropertyGroup" % (label, len(shown)))
            if not any(p.get("panel_visibility") == "advanced" for p in shown):
                failures.append("%s: %d properties and none advanced" % (label, len(shown)))
for failure in failures:
    print("FAIL:", failure)
print("%d proxies, %d failures" % (proxies, len(failures)))
sys.exit(1 if failures or not proxies else 0)
