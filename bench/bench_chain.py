#!/usr/bin/env python3
"""Path chaining benchmark: ordering a path's edges into one chain.

Every recompute that the 3D view follows (path arrows, target triads) and
every Generate reads the path's edges and chains them, so this cost is paid
on each change of a big drawing. Measured against FreeCAD's own
``Part.sortEdges`` (OCC, C++) on the same shuffled edges, in the same run.

    /usr/bin/python3 tools/freecad_run.py --clean-stdout bench/bench_chain.py

Edges: a zig-zag polyline of N straight edges, shuffled, every second one
reversed (so both methods must search and flip). Best of 3, one process.
"""

import math
import platform
import random
import sys
import time

SIZES = (100, 1000, 5000, 20000)


def zigzag_edges(n, seed=1):
    import FreeCAD
    import Part
    V = FreeCAD.Vector
    points = [V(10.0 * k, 15.0 * math.sin(0.7 * k), 0.0) for k in range(n + 1)]
    edges = [Part.makeLine(points[k], points[k + 1]) if k % 2 else Part.makeLine(points[k + 1], points[k])
             for k in range(n)]
    random.Random(seed).shuffle(edges)
    return edges


def best_of(runs, function):
    best = math.inf
    for _ in range(runs):
        start = time.perf_counter()
        result = function()
        best = min(best, time.perf_counter() - start)
    return best, result


def main():
    import Part
    from CadRobotWB.core.geometry import chain_segments
    from CadRobotWB.objects.reader import segment_from_edge

    print("Path chaining, one process (%s, Python %s)" % (platform.machine(), platform.python_version()))
    print("%8s %14s %14s %16s %8s" % ("edges", "ours s", "ours/edge us", "Part.sortEdges s", "ratio"))
    for n in SIZES:
        edges = zigzag_edges(n)
        segments = [segment_from_edge(e, "Edge%d" % (k + 1), 0.1) for k, e in enumerate(edges)]
        ours, (ordered, closed) = best_of(3, lambda: chain_segments(segments, 0.01))
        peer, groups = best_of(3, lambda: Part.sortEdges(edges))
        assert len(ordered) == n and not closed, "our chain is incomplete"
        assert len(groups) == 1 and len(groups[0]) == n, "Part.sortEdges split the chain"
        print("%8d %14.4f %14.1f %16.4f %7.2fx" % (n, ours, 1e6 * ours / n, peer, peer / ours))
    print("ratio = Part.sortEdges time / ours (above 1: ours is faster)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
