"""Links FreeCAD cannot follow: links that form a cycle, links into a missing file.

FreeCAD follows an ``App::Link`` (or a shape built from linked objects) until
its recursion limit and then crashes the process (a segfault, FreeCAD 0.20),
so a document whose links form a cycle is refused before it is opened: from
the link properties its ``Document.xml`` holds, or, in an open document,
from the same properties read (never followed).  A link into another file
that was not loaded is named by that file.  No FreeCAD import here.
"""

import io
import os
import xml.etree.ElementTree as ElementTree
import zipfile

from ..errors import DocumentError

#: The properties FreeCAD follows to make an object's shape: an ``App::Link``'s linked
#: object, a link group's elements, a group's members (the shape of a link to a group holds
#: its members').  Other links (a sketch's support, a feature's base, PartDesign's hidden
#: links back to its body) may form cycles in valid documents and are not followed.
FOLLOWED = ("LinkedObject", "ElementList", "Group")
#: The XML elements of those properties' values and the attribute naming the object.
LINK_ELEMENTS = (("Link", "value"), ("XLink", "name"))


def find_cycle(graph):
    """One cycle of a directed graph, or None.

    Parameters
    ----------
    graph : dict of str to list of str
        Each node's successors (nodes missing as keys have none).

    Returns
    -------
    list of str or None
        The nodes of a cycle in link order, the first repeated at the end
        (``["A", "B", "A"]``; an object linking to itself: ``["A", "A"]``).
    """
    done, on_path = set(), {}
    for start in graph:
        if start in done:
            continue
        stack, path = [(start, iter(graph.get(start, ())))], [start]
        on_path[start] = 0
        while stack:
            node, successors = stack[-1]
            step = next(successors, None)
            if step is None:
                stack.pop()
                done.add(path.pop())
                on_path.pop(node, None)
            elif step in on_path:
                return path[on_path[step]:] + [step]
            elif step not in done:
                on_path[step] = len(path)
                path.append(step)
                stack.append((step, iter(graph.get(step, ()))))
    return None


def graph_of_document_xml(root):
    """Each object's :data:`FOLLOWED` links in a parsed ``Document.xml``: {name: [names]}.

    Parameters
    ----------
    root : xml.etree.ElementTree.Element
        The ``<Document>`` element.
    """
    graph = {}
    for obj in root.findall("./ObjectData/Object"):
        graph[obj.get("name")] = [
            element.get(attribute) for name in FOLLOWED
            for prop in obj.findall("./Properties/Property[@name='%s']" % name)
            for tag, attribute in LINK_ELEMENTS for element in prop.iter(tag)
            if element.get(attribute) and not element.get("file")]     # not another file's object
    return graph


def labels_of_document_xml(root):
    """{object name: label} of a parsed ``Document.xml``."""
    labels = {}
    for obj in root.findall("./ObjectData/Object"):
        value = obj.find("./Properties/Property[@name='Label']/String")
        if value is not None:
            labels[obj.get("name")] = value.get("value")
    return labels


def refuse_cycle_in_document_xml(root, path):
    """DocumentError naming the objects when the links of document file `path`
    (``Document.xml`` parsed as `root`) form a cycle."""
    cycle = find_cycle(graph_of_document_xml(root))
    if cycle is not None:
        raise DocumentError(_message("'%s'" % path, cycle, labels_of_document_xml(root)), cycle[0])


def refuse_cycle_in(doc):
    """DocumentError naming the objects when the links of the open document `doc` form a cycle."""
    graph = {o.Name: [linked.Name for linked in _followed(o)] for o in doc.Objects}
    cycle = find_cycle(graph)
    if cycle is not None:
        labels = {o.Name: o.Label for o in doc.Objects}
        raise DocumentError(_message("'%s'" % doc.Label, cycle, labels), cycle[0])


def _followed(obj):
    """The objects `obj`'s :data:`FOLLOWED` properties hold (read, not followed)."""
    linked = []
    for name in FOLLOWED:
        if name in obj.PropertiesList:
            value = obj.getPropertyByName(name)
            linked += [v for v in (value if isinstance(value, (list, tuple)) else [value])
                       if hasattr(v, "Name")]
    return linked


def _message(document, cycle, labels):
    shown = " -> ".join("'%s'" % labels.get(name, name) if labels.get(name, name) == name
                        else "'%s' (%s)" % (labels[name], name) for name in cycle)
    return ("Document %s: the links of %s form a cycle, which FreeCAD cannot follow. Open it in "
            "FreeCAD and point one of these links at another object." % (document, shown))


def missing_link_file(obj, most=100):
    """The file of another document a link (or a chain of links) points into when that
    file was not loaded (missing, moved), else None.

    Parameters
    ----------
    obj : App.DocumentObject
        Any object; only ``App::Link``-like objects (a ``LinkedObject`` property) are
        followed, at most `most` links deep.

    Returns
    -------
    str or None
        The file as the link holds it, made absolute against the document's
        folder when it is relative.
    """
    for _ in range(most):
        if "LinkedObject" not in obj.PropertiesList:
            return None
        target = obj.LinkedObject
        if isinstance(target, (list, tuple)):
            target = target[0] if target else None
        if target is None:
            return _linked_file(obj)
        obj = target
    return None


def _linked_file(link):
    """The ``file`` of `link`'s ``LinkedObject`` as saved (FreeCAD's property dump), or None."""
    try:
        dump = link.dumpPropertyContent("LinkedObject")
        with zipfile.ZipFile(io.BytesIO(bytes(dump))) as archive:
            root = ElementTree.fromstring(archive.read(archive.namelist()[0]))
    except Exception:  # noqa: BLE001 -- an older FreeCAD or another format: no file to name
        return None
    element = root if root.tag == "XLink" else root.find(".//XLink")
    name = element.get("file") if element is not None else None
    if not name:
        return None
    folder = os.path.dirname(getattr(link.Document, "FileName", "") or "")
    return os.path.normpath(os.path.join(folder, name))
