#!/usr/bin/python3
"""Writes examples/showcase/*.json: seed 000's showcase shapes (its figures 4.9 to 4.17)
rebuilt with FRepCAD's nodes, each with an export box and resolution. `make test` exports
every one of them and checks it printable (tests/test_mesher.cpp, ShowcasePrintable).

    PYTHONPATH=build/python /usr/bin/python3 examples/make_showcase.py
"""

import math
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(os.path.dirname(HERE), "build", "python"))
import frepcore as fc  # noqa: E402

OUT = os.path.join(HERE, "showcase")


def bar():
    return fc.box((2, 0.5, 0.5), (-1, -0.25, -0.25))


def shapes():
    cross = [fc.box((1.6, 0.5, 0.5), (-0.8, -0.25, -0.25)), fc.box((0.5, 0.5, 1.6), (-0.25, -0.25, -0.8))]
    yield "blend_narrow", "Figure 4.9: blend union of two bars, a narrow fillet", \
        fc.blend_union(*cross, a0=0.2, a1=0.2, a2=0.2)
    yield "blend_wide", "Figure 4.9: blend union of two bars, a wide fillet", \
        fc.blend_union(*cross, a0=0.3, a1=1.0, a2=1.0)
    yield "blend_uneven", "Figure 4.9: blend union reaching far along the second bar only", \
        fc.blend_union(*cross, a0=0.3, a1=0.2, a2=1.0)
    spheres = [fc.sphere(0.5, (-0.45, 0, 0)), fc.sphere(0.5, (0.45, 0, 0))]
    yield "bounded_blend", "Figure 4.10: bounded blending of spheres, the fillet only where a " \
        "third sphere bounds it", \
        fc.bounded_blend(spheres[0], spheres[1], fc.sphere(0.45, (0, 0.4, 0)), a0=0.4, a3=0.2)
    yield "taper", "Figure 4.11: a box tapered along its height", \
        fc.box((1, 1, 2), (-0.5, -0.5, -1)).taper(0.3, 2, 1.0, (0, 0, 1), (0, 0, -1))
    yield "bend", "Figure 4.12: a box bent by 90 degrees", \
        fc.box((2, 0.4, 0.4), (0, -0.2, -0.2)).bend(direction=(1, 0, 0), toward=(0, 0, 1),
                                                      angle=90, length=2)
    yield "twist", "Figure 4.12: a box twisted by 180 degrees over its height", \
        fc.box((0.8, 0.8, 2), (-0.4, -0.4, -1)).twist(90)
    yield "deform_point", "Figure 4.12: a box with a point pulled out of its top", \
        fc.box((1.6, 1.6, 0.6), (-0.8, -0.8, -0.3)).deform_point(
            point=(0, 0, 0.3), displacement=(0, 0, 0.4), radius=0.6)
    path = [(-1, 0, 0), (-0.3, 0.6, 0.2), (0.4, -0.2, 0.5), (1, 0.4, 0)]
    yield "sweep", "Figure 4.13: a sphere swept along a curve", \
        fc.sweep(path, radius1=0.2, radius2=0.1)
    for name, d in (("offset_in", -0.15), ("offset_out", 0.15)):
        yield name, "Figure 4.14: a torus offset by %g" % d, fc.torus(0.8, 0.3).offset(d)
    yield "metamorphosis", "Figure 4.15: half way from a cone to a torus", \
        fc.metamorphosis(fc.cone(1.0, 0.2, 1.6, (0, 0, -0.8)), fc.torus(0.6, 0.3), t=0.5)
    grid = [(0.5 * i - 1, 0.5 * j - 1, 0) for i in range(5) for j in range(5)]
    yield "instancer_grid", "Figure 4.16: a torus instanced on a grid, rings linked into a " \
        "mesh", fc.torus(major_radius=0.3, minor_radius=0.07).instancer(positions=grid)
    core = [(math.cos(2 * math.pi * i / 24), math.sin(2 * math.pi * i / 24), 0) for i in range(24)]
    rings = fc.torus(major_radius=0.2, minor_radius=0.05).instancer(positions=core)
    yield "instancer_torus", "Figure 4.17: rings instanced along a torus's core circle, " \
        "chained, then intersected with a bigger torus", \
        fc.intersection(rings, fc.torus(major_radius=1.0, minor_radius=0.2))


def main():
    os.makedirs(OUT, exist_ok=True)
    for name, description, shape in shapes():
        box, cell = fc.automatic_box(shape, cells=64, padding_cells=3)
        text = shape.to_json(bbox=box, resolution=cell, description=description)
        path = os.path.join(OUT, name + ".json")
        with open(path + ".tmp", "w") as f:
            f.write(text)
        os.replace(path + ".tmp", path)
        print("wrote", os.path.relpath(path, os.path.dirname(HERE)))


if __name__ == "__main__":
    main()
