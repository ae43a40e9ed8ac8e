# SPDX-License-Identifier: GPL-3.0-or-later
"""The plugin's ParaView help has a page for every proxy, and the overview page with its pictures.

ParaView builds one help page per proxy from the server-manager XML, but splits them apart as a CMake list: an
unbalanced square bracket in any proxy's documentation (a half-open range such as "(0, 1]") silently merges every
later page into the one before. This test catches that.

    python3 test_help_pages.py --xml-dir sources/leaf/vtk sources/tree/vtk ... --help-dir build/paraview_plugin/paraview_help
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ElementTree

parser = argparse.ArgumentParser()
parser.add_argument("--xml-dir", required=True, nargs="+", help="the folders holding the proxy XML")
parser.add_argument("--help-dir", required=True)
arguments = parser.parse_args()

failures = []
expected = []
proxies = {}  # name -> the properties its panel shows
for name, path in sorted((n, os.path.join(d, n)) for d in arguments.xml_dir for n in os.listdir(d)):
    if not name.endswith(".xml"):
        continue
    root = ElementTree.parse(path).getroot()
    for group in root.iter("ProxyGroup"):
        for proxy in group:
            # internal_* groups (a writer's own proxy under its gathering writer) are not shown to users.
            if proxy.get("name") and not group.get("name").startswith("internal_"):
                expected.append("%s.%s.html" % (group.get("name"), proxy.get("name")))
                proxies[proxy.get("name")] = [p.get("name") for p in proxy if p.tag.endswith("Property")
                                              and p.get("information_only") != "1"
                                              and p.get("panel_visibility") != "never"]
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
# A page per proxy of our own (PlantMorph.<name>.html, written by paraview_plugin/write_proxy_help_pages.py from
# docs/proxy-pages.json and the XML): what it does, its paper, a picture that is in the help,
# and every property its panel shows.
for name, properties in sorted(proxies.items()):
    page_file = os.path.join(arguments.help_dir, "PlantMorph.%s.html" % name)
    if not os.path.exists(page_file):
        failures.append("no help page PlantMorph.%s.html" % name)
        continue
    page = open(page_file).read()
    if 'href="PlantMorph.%s.html"' % name not in overview:
        failures.append("PlantMorph.html does not link to PlantMorph.%s.html" % name)
    if "<p><i>From " not in page:
        failures.append("PlantMorph.%s.html does not say which paper it comes from" % name)
    images = [part.split('"')[0] for part in page.split('src="')[1:]]
    if not images:
        failures.append("PlantMorph.%s.html has no picture" % name)
    for image in images:
        if not os.path.exists(os.path.join(arguments.help_dir, image)):
            failures.append("PlantMorph.%s.html shows %s, which is not in the help" % (name, image))
    for prop in properties:
        if "<b>%s</b>" % prop not in page:
            failures.append("PlantMorph.%s.html does not describe its property %s" % (name, prop))
for failure in failures:
    print("FAIL:", failure)
print("%d proxies, %d failures" % (len(expected), len(failures)))
sys.exit(1 if failures or not expected else 0)
