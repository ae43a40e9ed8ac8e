# SPDX-License-Identifier: GPL-3.0-or-later
"""What the GUI tests' check macros report of a pipeline object (gui_playback puts this folder on the macros'
PYTHONPATH): its label, its inputs in order ("Property=source:port") and per output port [points, cells], or
[rows, rows] for a table."""
from paraview import servermanager
from paraview.simple import OutputPort

INPUT_PROPERTIES = ("Input", "Veins", "Leaf", "Strokes", "MergeTree")


def describe(proxy):
    ports = []
    for port in range(proxy.SMProxy.GetNumberOfOutputPorts()):
        info = OutputPort(proxy, port).GetDataInformation()
        if info.GetDataSetTypeAsString() == "vtkTable":
            ports.append([info.GetNumberOfRows(), info.GetNumberOfRows()])
        else:
            ports.append([info.GetNumberOfPoints(), info.GetNumberOfCells()])
    inputs = []
    for name in INPUT_PROPERTIES:
        prop = proxy.SMProxy.GetProperty(name)
        for i in range(prop.GetNumberOfProxies() if prop is not None else 0):
            source = servermanager.ProxyManager().GetProxyName("sources", prop.GetProxy(i))
            inputs.append("%s=%s:%d" % (name, source, prop.GetOutputPortForConnection(i)))
    return {"label": proxy.GetXMLLabel(), "ports": ports, "inputs": inputs}
