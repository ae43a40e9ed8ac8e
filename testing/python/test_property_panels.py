# SPDX-License-Identifier: GPL-3.0-or-later
"""Every PlantMorph proxy gives a tidy Properties panel (plain python3 over the server-manager XML):

- it is in the PlantMorph menu (Sources or Filters), or, for a reader, opens its files from File > Open;
- its label (the menu entry) is spaced words, "Leaf Outline Source", not "LeafOutlineSource";
- the proxy and every property it shows have documentation: ParaView shows it as the panel's tooltips and help;
  a property's is a tooltip: one or two plain sentences of at most 250 characters, no paper symbols such as "b_y"
  (the long explanation goes in the Documentation's long_help, which the help page shows, or the proxy's);
- a proxy with more than 8 properties puts them in groups (the panel's sections) and hides some as advanced (the
  gear button shows them), so the default panel shows what most users change;
- every numeric property a user types has a range domain (the panel then rejects or clamps nonsense);
- a property of several numbers in a row (not a repeatable list) labels each box (ShowComponentLabels);
- every list (repeat_command) is labelled: ParaView 5.11 shows a list of doubles with its label only when it has
  ShowComponentLabels, which also gives each column its header, so every list of doubles has one label per column;
  it shows a list of whole numbers with no label at all, so such a list is alone in a labelled PropertyGroup;
- a preset never hides what it sets: a property used only with a Custom preset (a decorator on a ...Preset property
  with value 0) is greyed out (mode "enabled_state"), not hidden, so a user sees it under a named preset;
- a text property of several strings (not a list) is not shown: ParaView 5.11 gives it one text box that shows
  none of its values (use one property per string, e.g. a column menu with an ArrayListDomain).

    python3 test_property_panels.py --xml-dir sources/leaf/vtk sources/tree/vtk ...
"""
import argparse
import os
import re
import sys
import xml.etree.ElementTree as ElementTree

parser = argparse.ArgumentParser()
parser.add_argument("--xml-dir", required=True, nargs="+", help="the folders holding the proxy XML")
arguments = parser.parse_args()

# A sentence ends at ". ", "! " or "? " before a capital, except after an abbreviation or a lone letter ("e.g.",
# "i.e.", "Fig.", "sec.", "P. Prusinkiewicz") and inside numbers (no space follows the point there).
ABBREVIATION = re.compile(r"(\b(e\.g|i\.e|etc|cf|vs|approx|Fig|Figs|Eq|Eqs|eq|eqs|sec|secs|No|al|Dr|resp)|\b[A-Za-z])\.$")
# Paper symbols a tooltip must say in words: b_y, a_x, u_3, k_n (a letter, an underscore, one or two letters or
# digits, as a word of its own; names such as paper_sim_x or Points_0 in quotes are column names, not symbols).
JARGON = re.compile(r"(?<![\w'])[a-zA-Z]_[a-zA-Z0-9]{1,2}\b(?!['_])")


def sentences(text):
    count = 1
    for end in re.finditer(r"[.!?](?=\s+[A-Z(])", text):
        if not ABBREVIATION.search(text[:end.end()]):
            count += 1
    return count


def list_label_failures(proxy, prop):
    """Why a list property (repeat_command) shows without labels in ParaView 5.11's panel, if it does."""
    name = prop.get("name")
    columns = int(prop.get("number_of_elements_per_command") or 1)
    if prop.tag == "DoubleVectorProperty":
        labels = prop.findall("Hints/ShowComponentLabels/ComponentLabel")
        if len(labels) != columns or not all(l.get("label") for l in labels):
            return ["list %s of %d column(s) has %d column labels: ParaView shows neither its label nor its column "
                    "headers without ShowComponentLabels naming each column" % (name, columns, len(labels))]
        return []
    if prop.tag == "IntVectorProperty":
        groups = [g for g in proxy.findall("PropertyGroup") if any(p.get("name") == name for p in g)]
        if columns > 1:
            return ["list %s of whole numbers has %d columns: ParaView 5.11 gives them no headers" % (name, columns)]
        if len(groups) != 1 or len(groups[0]) != 1 or not groups[0].get("label"):
            return ["list %s of whole numbers shows no label in ParaView 5.11: put it alone in a labelled "
                    "PropertyGroup" % name]
    return []


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
            else:
                tip = " ".join("".join(text.itertext()).split())
                if len(tip) > 250:
                    failures.append("%s: property %s has a %d-character tooltip (at most 250: a sentence or two; "
                                    "the explanation goes in long_help, the help page)" % (label, prop.get("name"),
                                                                                           len(tip)))
                if sentences(tip) > 2:
                    failures.append("%s: property %s has a tooltip of %d sentences (at most 2): %r" % (
                        label, prop.get("name"), sentences(tip), tip))
                if JARGON.search(tip):
                    failures.append("%s: property %s's tooltip uses a paper symbol %r (say it in words)" % (
                        label, prop.get("name"), JARGON.search(tip).group(0)))
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
            for decorator in prop.iter("PropertyWidgetDecorator"):
                if ((decorator.get("property") or "").endswith("Preset") and decorator.get("value") == "0"
                        and decorator.get("mode") != "enabled_state"):
                    failures.append("%s: property %s is hidden under a named %s (grey it out: mode enabled_state)"
                                    % (label, prop.get("name"), decorator.get("property")))
            if prop.get("repeat_command") == "1":
                failures.extend("%s: %s" % (label, f) for f in list_label_failures(proxy, prop))
            if (prop.tag == "StringVectorProperty" and prop.get("repeat_command") != "1"
                    and int(prop.get("number_of_elements") or 1) > 1):
                failures.append("%s: property %s holds %s strings in one text box that shows none of them (one "
                                "property per string)" % (label, prop.get("name"), prop.get("number_of_elements")))
        if len(shown) > 8:
            if not proxy.findall("PropertyGroup"):
                failures.append("%s: %d properties and no PropertyGroup" % (label, len(shown)))
            if not any(p.get("panel_visibility") == "advanced" for p in shown):
                failures.append("%s: %d properties and none advanced" % (label, len(shown)))
for failure in failures:
    print("FAIL:", failure)
print("%d proxies, %d failures" % (proxies, len(failures)))
sys.exit(1 if failures or not proxies else 0)
