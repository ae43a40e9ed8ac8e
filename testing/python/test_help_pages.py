"""The plugin's ParaView help has a page for every proxy, and the overview page with its pictures.

ParaView builds one help page per proxy from the server-manager XML, but splits them apart as a CMake list: an
unbalanced square bracket in any proxy's documentation (a half-open range such as "(0, 1]") silently merges every
later page into the one before. This test catches that.

    python3 test_help_pages.py --xml-dir xml --help-dir build/paraview_plugin/paraview_help
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ElementTree

parser = argparse.ArgumentParser()
parser.add_argument("--xml-dir", required=True)
parser.add_argument("--help-dir", required=True)
arguments = parser.parse_args()

failures = []
expected = []
for name in sorted(os.listdir(arguments.xml_dir)):
    if not name.endswith(".xml"):
        continue
    root = ElementTree.parse(os.path.join(arguments.xml_dir, name)).getroot()
    for group in root.iter("ProxyGroup"):
        for proxy in group:
            if proxy.get("name"):
                expected.append("%s.%s.html" % (group.get("name"), proxy.get("name")))
        for documentation in group.iter("Documentation"):
            text = "".join(documentation.itertext()) + (documentation.get("long_help") or "")
            if text.count("[") != text.count("]"):
                failures.append("%s: documentation with unbalanced square brackets: %r" % (name, text.strip()[:120]))
for page in expected + ["PlantMorph.html"]:
    if not os.path.exists(os.path.join(arguments.help_dir, page)):
        failures.append("no help page %s" % page)
overview = open(os.path.join(arguments.help_dir, "PlantMorph.html")).read() if os.path.exists(
    os.path.join(arguments.help_dir, "PlantMorph.html")) else ""
for image in [part.split('"')[0] for part in overview.split('src="')[1:]]:
    if not os.path.exists(os.path.join(arguments.help_dir, image)):
        failures.append("PlantMorph.html shows %s, which is not in the help" % image)
for failure in failures:
    print("FAIL:", failure)
print("%d proxies, %d failures" % (len(expected), len(failures)))
sys.exit(1 if failures or not expected else 0)
