# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes the plugin's help page of every proxy, PlantMorph.<Proxy>.html: what it does, its paper and pictures (from
docs/proxy-pages.json) and the table of the properties its panel shows, read from the proxy's server-manager XML
(each property's tooltip and, below it, the long explanation in its Documentation's long_help), so the page never
disagrees with the panel's tooltips. Run by the build (paraview_plugin/CMakeLists.txt) into the help folder ParaView
compiles.

    python3 write_proxy_help_pages.py --xml-dir sources/leaf/vtk sources/tree/vtk ... --pages docs/proxy-pages.json --out build/.../paraview_help
"""
import argparse
import html
import json
import os
import xml.etree.ElementTree as ElementTree

PAGE = """<html>
<head><title>%(label)s (PlantMorph)</title></head>
<body>
<p><a href="PlantMorph.html">PlantMorph</a> &gt; %(label)s</p>
<h1>%(label)s</h1>
<p><i>From %(paper)s. In ParaView: %(menu)s.</i></p>
<p>%(description)s</p>
%(pictures)s
<h2>Properties</h2>
<p>Ranges and defaults as the Properties panel shows them; the generated reference page is
<a href="%(group)s.%(name)s.html">%(group)s.%(name)s</a>.</p>
<table border="1" cellpadding="3">
<tr><th>property</th><th>what it does</th></tr>
%(rows)s
</table>
</body>
</html>
"""


def proxies(xml_dirs):
    """(group, proxy element) of every proxy in the XML files of the folders, in order of file name."""
    files = sorted((name, os.path.join(d, name)) for d in xml_dirs for name in os.listdir(d) if name.endswith(".xml"))
    for _, path in files:
        if True:
            root = ElementTree.parse(path).getroot()
            for group in root.iter("ProxyGroup"):
                for proxy in group:
                    if proxy.get("name"):
                        yield group.get("name"), proxy


def property_rows(proxy):
    rows = []
    for prop in proxy:
        if (not prop.tag.endswith("Property") or prop.get("information_only") == "1"
                or prop.get("panel_visibility") == "never"):
            continue
        documentation = prop.find("Documentation")
        text = " ".join("".join(documentation.itertext()).split()) if documentation is not None else ""
        # The tooltip (a sentence or two), then the long explanation the tooltip leaves out (long_help), if any.
        details = " ".join((documentation.get("long_help") or "").split()) if documentation is not None else ""
        cell = html.escape(text) + ("<br/><small>%s</small>" % html.escape(details) if details else "")
        advanced = " (advanced)" if prop.get("panel_visibility") == "advanced" else ""
        rows.append("<tr><td><b>%s</b>%s</td><td>%s</td></tr>" % (prop.get("name"), advanced, cell))
    return "\n".join(rows)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--xml-dir", required=True, nargs="+", help="the folders holding the proxy XML")
    parser.add_argument("--pages", required=True, help="docs/proxy-pages.json")
    parser.add_argument("--out", required=True)
    arguments = parser.parse_args()
    with open(arguments.pages) as f:
        pages = json.load(f)
    os.makedirs(arguments.out, exist_ok=True)
    for group, proxy in proxies(arguments.xml_dir):
        name = proxy.get("name")
        if name not in pages:
            continue  # the help_pages test reports a proxy without a page
        page = pages[name]
        label = proxy.get("label")
        hints = proxy.find("Hints")
        if hints is not None and hints.find("ReaderFactory") is not None:
            menu = "File &gt; Open (a reader)"
        elif group == "writers" or (hints is not None and hints.find("WriterFactory") is not None):
            menu = "File &gt; Save Data (a writer)"
        else:
            menu = "%s &gt; PlantMorph &gt; %s" % ("Sources" if group == "sources" else "Filters", label)
        pictures = "\n".join('<p><img src="images/%s" width="700"/></p>' % p for p in page["pictures"])
        with open(os.path.join(arguments.out, "PlantMorph.%s.html" % name), "w") as f:
            f.write(PAGE % dict(label=label, paper=page["paper"], menu=menu, description=html.escape(page["description"]),
                                pictures=pictures, group=group, name=name, rows=property_rows(proxy)))


if __name__ == "__main__":
    main()
