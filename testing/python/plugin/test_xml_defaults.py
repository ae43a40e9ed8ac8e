# SPDX-License-Identifier: GPL-3.0-or-later
"""pvpython: every proxy's XML default is its VTK class's own default.

The proxy XML (xml/*.xml) is the one place for a property's default: pvpython and the GUI push it, and the help
pages print it. A C++ or VTK user, or a state file that omits a property, gets the class's constructor value
instead, so the two must agree. For every proxy in xml/ and every Int/Double/IdType/String VectorProperty with
default_values (information_only properties and inputs skipped), the class is made through the client-server
interpreter (a bare `New`, no property pushed) and the property's getter is called the same way; every element
must equal the XML's (doubles exactly, as ParaView parses the XML's text).

The getter is found by one rule: command `Set<Name>` is read by `Get<Name>` (a scalar or a vector macro, or a
string). Commands without such a getter:
  * repeated rows (`repeat_command="1"`, `Add<Row>` with a `clean_command`): the number of rows the XML's default
    holds is compared with `GetNumberOf<PropertyName>()`; where the class has no such count, the property is listed
    in NO_GETTER below with its reason;
  * anything else: its getter is named in OTHER_GETTERS (a getter with an index argument reads element i), or the
    property is listed in NO_GETTER. A property that fits no rule and is in neither list fails the test, so a new
    property cannot be skipped silently.
Properties whose XML default is deliberately not the class's are listed in DIFFERENT_ON_PURPOSE (empty today).

    pvpython test_xml_defaults.py --plugin PlantMorph.so --work DIR [--xml-dir xml/]
"""
import glob
import os
import xml.etree.ElementTree as ElementTree

from plantmorph_testing import Checks, load_plugin, parse_arguments

root = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
arguments = parse_arguments([("--xml-dir", dict(default=os.path.join(root, "xml")))])

from paraview.simple import *  # noqa: F401,F403
from paraview.modules.vtkRemotingClientServerStream import (vtkClientServerInterpreterInitializer,
                                                             vtkClientServerStream)

load_plugin(arguments.plugin, globals())
checks = Checks()

# (proxy, property): (getter, index or None per element): properties whose setter has no same-named getter.
OTHER_GETTERS = {
    # The column menus and the older three-name property all end in the column in use (the menu's own name, else
    # the three-name property's, else "auto"), which GetMeasuredColumn(i) / GetSimulatedColumn(i) return.
    ("TrajectoryComparisonFilter", "MeasuredX"): ("GetMeasuredColumn", [0]),
    ("TrajectoryComparisonFilter", "MeasuredY"): ("GetMeasuredColumn", [1]),
    ("TrajectoryComparisonFilter", "MeasuredZ"): ("GetMeasuredColumn", [2]),
    ("TrajectoryComparisonFilter", "SimulatedX"): ("GetSimulatedColumn", [0]),
    ("TrajectoryComparisonFilter", "SimulatedY"): ("GetSimulatedColumn", [1]),
    ("TrajectoryComparisonFilter", "SimulatedZ"): ("GetSimulatedColumn", [2]),
    ("TrajectoryComparisonFilter", "MeasuredColumns"): ("GetMeasuredColumn", [0, 1, 2]),
    ("TrajectoryComparisonFilter", "SimulatedColumns"): ("GetSimulatedColumn", [0, 1, 2]),
}
# (proxy, property): why the class's default cannot be read (the property is then not compared).
NO_GETTER = {
    ("LeafOutlineSource", "MidveinPoints"): "a row list (AddMidveinPoint) without a count getter; default empty",
    ("LeafOutlineSource", "LeftMarginPoints"): "a row list (AddLeftMarginPoint) without a count getter; default empty",
    ("LeafOutlineSource", "RightMarginPoints"): "a row list (AddRightMarginPoint) without a count getter; "
                                                "default empty",
    ("TreeFromSketchSource", "DeletedBranches"): "a row list (AddDeletedBranch) without a count getter; "
                                                 "default empty",
    ("TreeFromSketchSource", "BranchOverrides"): "a row list (AddBranchOverride) without a count getter; "
                                                 "default empty",
}
# (proxy, property): why the XML's default is deliberately not the class's.
DIFFERENT_ON_PURPOSE = {}

interpreter = vtkClientServerInterpreterInitializer.GetGlobalInterpreter()
OBJECT_ID = 7001  # an id the interpreter does not use in a pvpython without a server


def run(text):
    """Runs a client-server stream written as text (vtkClientServerStream::StreamFromString's syntax); returns
    (ok, the reply stream)."""
    stream = vtkClientServerStream()
    if not stream.StreamFromString(text):
        raise ValueError("not a client-server stream: %r" % text)
    ok = interpreter.ProcessStream(stream)
    return ok, interpreter.GetLastResult()


def reply_values(reply):
    """The values of a getter's reply: a list of numbers or strings, or None when it is not a reply with one
    argument."""
    if reply.GetCommand(0) != vtkClientServerStream.Reply or reply.GetNumberOfArguments(0) != 1:
        return None
    kind = vtkClientServerStream.GetStringFromType(reply.GetArgumentType(0, 0))
    if kind == "string_value":
        # The text form is "Reply <string>", or "Reply string(<string>)" for an empty string or one with parentheses
        # (escaped by backslashes), or "Reply string0" for a null pointer.
        text = reply.StreamToString()[len("Reply "):].rstrip("\n")
        if text == "string0":
            return [None]
        if text.startswith("string(") and text.endswith(")"):
            text = text[len("string("):-1].replace("\\(", "(").replace("\\)", ")").replace("\\\\", "\\")
        return [text]
    if kind.endswith("_array"):
        length = [0]
        reply.GetArgumentLength(0, 0, length)
        values = [0.0] * length[0]
        reply.GetArgument(0, 0, values, length[0])
        return values
    value = [False] if kind == "bool_value" else [0.0]
    return [float(value[0])] if reply.GetArgument(0, 0, value) else None


def call(getter, index=None):
    """The class's value through `getter` (with an int argument when index is not None), or (None, error)."""
    argument = "" if index is None else " int32(%d)" % index
    ok, reply = run("Invoke id(%d) %s%s" % (OBJECT_ID, getter, argument))
    if not ok:
        return None, reply.StreamToString().strip()
    values = reply_values(reply)
    return values, None if values is not None else "unexpected reply %r" % reply.StreamToString()


def xml_default(prop):
    """The XML's default_values as ParaView reads it: numbers, or strings split on ';' (String properties of
    several elements), or [] for 'none'."""
    text = prop.get("default_values")
    if text == "none":
        return []
    if prop.tag == "StringVectorProperty":
        count = int(prop.get("number_of_elements", "1"))
        return text.split(";") if count > 1 else [text]
    return [float(v) for v in text.split()]


def same(xml_value, cxx_value):
    if isinstance(xml_value, str) or isinstance(cxx_value, str) or cxx_value is None:
        return xml_value == (cxx_value if cxx_value is not None else "")
    return float(xml_value) == float(cxx_value)


def class_values(proxy_name, prop):
    """The class's default for `prop`: (values, None), or (None, why not readable), or ('skip', reason)."""
    name = prop.get("name")
    key = (proxy_name, name)
    if key in NO_GETTER:
        return "skip", NO_GETTER[key]
    if key in OTHER_GETTERS:
        getter, indices = OTHER_GETTERS[key]
        values = []
        for i in indices:
            value, error = call(getter, i)
            if error:
                return None, "%s(%d): %s" % (getter, i, error)
            values += value
        return values, None
    command = prop.get("command", "")
    if prop.get("repeat_command") == "1":
        count, error = call("GetNumberOf" + name)
        if error:
            return None, "a row list without GetNumberOf%s() (%s): list it in NO_GETTER with the reason" % (
                name, error)
        per_row = int(prop.get("number_of_elements_per_command", "1"))
        return ["rows", int(count[0]) * per_row], None
    if not command.startswith("Set"):
        return None, "command %s has no getter rule: name one in OTHER_GETTERS or list it in NO_GETTER" % command
    return call("Get" + command[len("Set"):])


files = sorted(glob.glob(os.path.join(arguments.xml_dir, "*.xml")))
checks.check(len(files) >= 11, "the proxy XML found in %s (%d files)" % (arguments.xml_dir, len(files)))
compared = 0
listed = set()
for path in files:
    for proxy in ElementTree.parse(path).getroot().iter():
        class_name = proxy.get("class")
        if not class_name or not proxy.tag.endswith("Proxy"):
            continue
        proxy_name = proxy.get("name")
        ok, reply = run("New %s id(%d)" % (class_name, OBJECT_ID))
        checks.check(ok, "%s: the client-server interpreter makes a %s (%s)" % (proxy_name, class_name,
                                                                              reply.StreamToString().strip()))
        if not ok:
            continue
        for prop in proxy:
            if not prop.tag.endswith("VectorProperty") or prop.tag == "ProxyProperty":
                continue
            if prop.get("information_only") == "1" or prop.get("default_values") is None:
                continue
            name = prop.get("name")
            key = (proxy_name, name)
            expected = xml_default(prop)
            values, error = class_values(proxy_name, prop)
            if values == "skip":
                listed.add(key)
                print("not compared: %s.%s (%s)" % (proxy_name, name, error))
                continue
            if key in DIFFERENT_ON_PURPOSE:
                listed.add(key)
                print("different on purpose: %s.%s (%s)" % (proxy_name, name, DIFFERENT_ON_PURPOSE[key]))
                continue
            if error:
                checks.check(False, "%s.%s: the class's default cannot be read: %s" % (proxy_name, name, error))
                continue
            if values and values[0] == "rows":
                equal = values[1] == len(expected)
                shown = "%d numbers (%d rows)" % (values[1], values[1] // int(prop.get(
                    "number_of_elements_per_command", "1")))
            else:
                equal = len(values) == len(expected) and all(same(x, c) for x, c in zip(expected, values))
                shown = values
            compared += 1
            checks.check(equal, "%s.%s: XML default %s, C++ (%s) default %s" % (
                proxy_name, name, prop.get("default_values"), class_name, shown))
        run("Delete id(%d)" % OBJECT_ID)
stale = [key for key in list(OTHER_GETTERS) + list(NO_GETTER) + list(DIFFERENT_ON_PURPOSE)
         if key not in listed and key not in OTHER_GETTERS]
checks.check(not stale, "every listed exception is a property with an XML default: %s" % stale)
checks.check(compared > 200, "%d properties compared" % compared)
checks.finish()
