#!/usr/bin/env python3
"""Writes the workbench's SVG icons into Mod/FRep/resources/icons.

Icons are drawn here from a few shapes so they stay consistent (64x64, one light source from
the upper left, solids in blue, operations showing their inputs in grey and the result in
blue). Run after adding a node type that deserves its own icon; a type without one falls back
to its category's icon (category-<name>.svg) and then to frep.svg.

    python3 scripts/make_icons.py
"""

import os
import sys

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "Mod", "FRep",
                   "resources", "icons")

BLUE = ("#8fc3ff", "#1d5fae")
GREY = ("#e4e4e4", "#8a8a8a")
ORANGE = ("#ffd08a", "#d9730d")
GREEN = ("#b6f0a8", "#2f8f2f")
STROKE = "#12355f"


def svg(body, defs=""):
    return ('<svg xmlns="http://www.w3.org/2000/svg" width="64" height="64" '
            'viewBox="0 0 64 64">\n<defs>\n%s</defs>\n%s</svg>\n' % (defs, body))


def radial(name, colours):
    light, dark = colours
    return ('<radialGradient id="%s" cx="0.35" cy="0.3" r="0.8">'
            '<stop offset="0" stop-color="%s"/><stop offset="1" stop-color="%s"/>'
            '</radialGradient>\n' % (name, light, dark))


def linear(name, colours, x2=1, y2=0):
    light, dark = colours
    return ('<linearGradient id="%s" x1="0" y1="0" x2="%g" y2="%g">'
            '<stop offset="0" stop-color="%s"/><stop offset="1" stop-color="%s"/>'
            '</linearGradient>\n' % (name, x2, y2, light, dark))


def stroke(width=2):
    return 'stroke="%s" stroke-width="%g" stroke-linejoin="round"' % (STROKE, width)


def arrow(x1, y1, x2, y2, colour=STROKE, width=4):
    """A straight arrow with a triangular head at (x2, y2)."""
    import math
    dx, dy = x2 - x1, y2 - y1
    length = math.hypot(dx, dy)
    ux, uy = dx / length, dy / length
    head = 10
    bx, by = x2 - ux * head, y2 - uy * head
    px, py = -uy * head * 0.6, ux * head * 0.6
    return ('<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="%s" stroke-width="%g" '
            'stroke-linecap="round"/>\n<path d="M%g,%g L%g,%g L%g,%g Z" fill="%s"/>\n'
            % (x1, y1, bx, by, colour, width, x2, y2, bx + px, by + py, bx - px, by - py,
               colour))


# -- solids --------------------------------------------------------------------------------
def sphere(cx=32, cy=32, r=26, fill="url(#b)"):
    return '<circle cx="%g" cy="%g" r="%g" fill="%s" %s/>\n' % (cx, cy, r, fill, stroke())


def cube(x=8, y=14, s=34, d=14, colours=BLUE, tag="c"):
    """An oblique cube: front face at (x, y), size s, depth offset d."""
    light, dark = colours
    front = '<rect x="%g" y="%g" width="%g" height="%g" fill="%s" %s/>\n' % (
        x, y + d, s, s, light, stroke())
    top = '<path d="M%g,%g L%g,%g L%g,%g L%g,%g Z" fill="%s" %s/>\n' % (
        x, y + d, x + d, y, x + d + s, y, x + s, y + d, "#ffffff" if colours == BLUE else light,
        stroke())
    side = '<path d="M%g,%g L%g,%g L%g,%g L%g,%g Z" fill="%s" %s/>\n' % (
        x + s, y + d, x + d + s, y, x + d + s, y + s, x + s, y + d + s, dark, stroke())
    return front + top + side


def cylinder_body():
    return ('<path d="M12,14 L12,50 A20,7 0 0 0 52,50 L52,14 Z" fill="url(#lb)" %s/>\n'
            '<ellipse cx="32" cy="14" rx="20" ry="7" fill="#dcecff" %s/>\n'
            % (stroke(), stroke()))


def cone_body():
    return ('<path d="M32,6 L10,50 A22,7 0 0 0 54,50 Z" fill="url(#lb)" %s/>\n'
            '<path d="M10,50 A22,7 0 0 1 54,50" fill="none" stroke="%s" stroke-width="1" '
            'stroke-dasharray="3,2"/>\n' % (stroke(), STROKE))


def torus_body():
    return ('<ellipse cx="32" cy="34" rx="28" ry="17" fill="url(#b)" %s/>\n'
            '<ellipse cx="32" cy="31" rx="12" ry="5.5" fill="#ffffff" %s/>\n'
            '<path d="M20,31 A12,6 0 0 0 44,31" fill="none" stroke="%s" stroke-width="2"/>\n'
            % (stroke(), stroke(), STROKE))


def ellipsoid_body():
    return ('<ellipse cx="32" cy="32" rx="28" ry="17" fill="url(#b)" %s '
            'transform="rotate(-25 32 32)"/>\n' % stroke())


def halfspace_body():
    return ('<path d="M4,40 L24,26 L60,26 L40,40 Z" fill="#dcecff" %s/>\n'
            '<path d="M4,40 L40,40 L40,60 L4,60 Z" fill="url(#lb)" %s/>\n'
            '<path d="M40,40 L60,26 L60,46 L40,60 Z" fill="#1d5fae" %s/>\n'
            % (stroke(), stroke(), stroke()) + arrow(32, 33, 32, 4, ORANGE[1], 3))


def small_solid(cx=22, cy=40, fill="url(#b)"):
    return sphere(cx, cy, 15, fill)


# -- operations ----------------------------------------------------------------------------
def two_circles(left_fill, right_fill, extra=""):
    return (sphere(24, 32, 18, left_fill) + sphere(40, 32, 18, right_fill) + extra)


def venn(mode):
    """Union, intersection or difference of two discs, the result in blue. Drawn with
    explicit arcs: Qt's SVG renderer (SVG Tiny) has no clip paths or masks."""
    defs = radial("b", BLUE) + radial("g", GREY)
    top, bottom = "32,15.875", "32,48.125"  # where the circles (24|40, 32) r 18 cross
    lens = "M%s A18,18 0 0 1 %s A18,18 0 0 1 %s Z" % (top, bottom, top)
    crescent = "M%s A18,18 0 1 0 %s A18,18 0 0 1 %s Z" % (top, bottom, top)
    outline = ('<circle cx="24" cy="32" r="18" fill="none" %s/>'
               '<circle cx="40" cy="32" r="18" fill="none" %s/>\n' % (stroke(), stroke()))
    if mode == "union":
        outer = "M%s A18,18 0 1 0 %s A18,18 0 1 0 %s Z" % (top, bottom, top)
        body = '<path d="%s" fill="url(#b)" %s/>\n' % (outer, stroke())
    elif mode == "intersection":
        body = ('<circle cx="24" cy="32" r="18" fill="url(#g)"/>'
                '<circle cx="40" cy="32" r="18" fill="url(#g)"/>\n'
                '<path d="%s" fill="url(#b)"/>\n' % lens + outline)
    else:  # difference: A minus B
        body = ('<circle cx="40" cy="32" r="18" fill="url(#g)" opacity="0.6"/>\n'
                '<path d="%s" fill="url(#b)"/>\n' % crescent + outline)
    return svg(body, defs)


def blend(mode):
    """Two discs joined (union) or cut (intersection) with a smooth fillet."""
    defs = radial("b", BLUE) + radial("g", GREY)
    if mode == "union":
        body = ('<path d="M22,13 C30,13 32,20 32,20 C32,20 34,13 42,13 A19,19 0 0 1 42,51 '
                'C34,51 32,44 32,44 C32,44 30,51 22,51 A19,19 0 0 1 22,13 Z" '
                'fill="url(#b)" %s/>\n' % stroke())
    else:
        body = ('<circle cx="22" cy="32" r="19" fill="url(#g)" opacity="0.5"/>'
                '<circle cx="42" cy="32" r="19" fill="url(#g)" opacity="0.5"/>\n'
                '<path d="M32,17 C38,22 39,28 39,32 C39,36 38,42 32,47 C26,42 25,36 25,32 '
                'C25,28 26,22 32,17 Z" fill="url(#b)" %s/>\n' % stroke())
    return svg(body, defs)


def complement():
    defs = radial("b", BLUE)
    body = ('<rect x="3" y="3" width="58" height="58" rx="4" fill="url(#b)" %s/>\n'
            '<circle cx="32" cy="32" r="16" fill="#ffffff" %s stroke-dasharray="4,3"/>\n'
            % (stroke(), stroke()))
    return svg(body, defs)


def translate():
    defs = radial("b", BLUE) + radial("g", GREY)
    return svg(small_solid(18, 44, "url(#g)") + small_solid(44, 20)
               + arrow(22, 40, 38, 24, ORANGE[1], 4), defs)


def rotate():
    defs = linear("lb", BLUE)
    body = cube(14, 20, 26, 10)
    body += ('<path d="M10,20 A24,24 0 0 1 50,12" fill="none" stroke="%s" stroke-width="4" '
             'stroke-linecap="round"/>\n<path d="M56,6 L54,20 L43,12 Z" fill="%s"/>\n'
             % (ORANGE[1], ORANGE[1]))
    return svg(body, defs)


def scale():
    defs = radial("b", BLUE) + radial("g", GREY)
    return svg(small_solid(18, 46, "url(#g)").replace('r="15"', 'r="10"')
               + sphere(38, 28, 22) + arrow(22, 42, 50, 14, ORANGE[1], 3), defs)


def transform():
    defs = linear("lb", BLUE)
    body = cube(16, 18, 28, 12)
    body += ('<text x="4" y="60" font-family="sans-serif" font-size="20" font-weight="bold" '
             'fill="%s">[M]</text>\n' % ORANGE[1])
    return svg(body, defs)


def polygonize():
    defs = radial("b", BLUE)
    pts = [(32, 6), (12, 18), (52, 18), (6, 38), (32, 30), (58, 38), (16, 56), (48, 56)]
    tris = [(0, 1, 4), (0, 4, 2), (1, 3, 4), (2, 4, 5), (3, 6, 4), (4, 6, 7), (4, 7, 5)]
    body = ""
    for t in tris:
        d = "M" + " L".join("%g,%g" % pts[i] for i in t) + " Z"
        body += '<path d="%s" fill="url(#b)" %s/>\n' % (d, stroke(1.5))
    return svg(body, defs)


def export():
    defs = radial("b", BLUE)
    body = ('<path d="M10,8 L38,8 L48,18 L48,58 L10,58 Z" fill="#ffffff" %s/>\n'
            '<path d="M38,8 L38,18 L48,18" fill="none" %s/>\n' % (stroke(), stroke()))
    body += sphere(26, 38, 12)
    body += arrow(36, 30, 60, 30, GREEN[1], 4)
    return svg(body, defs)


def preview():
    defs = radial("b", BLUE)
    body = ('<path d="M4,32 C16,12 48,12 60,32 C48,52 16,52 4,32 Z" fill="#ffffff" %s/>\n'
            % stroke())
    body += sphere(32, 32, 12)
    for x in (10, 22, 34, 46):
        body += '<rect x="%d" y="56" width="8" height="6" fill="%s"/>\n' % (
            x, ORANGE[1] if x < 40 else GREY[1])
    return svg(body, defs)


def frep():
    defs = radial("b", BLUE)
    body = ('<path d="M22,10 C30,10 32,18 32,18 C32,18 34,10 42,10 A20,20 0 0 1 42,50 '
            'C34,50 32,42 32,42 C32,42 30,50 22,50 A20,20 0 0 1 22,10 Z" fill="url(#b)" %s/>\n'
            '<text x="32" y="62" text-anchor="middle" font-family="sans-serif" '
            'font-size="13" font-weight="bold" fill="%s">F≥0</text>\n' % (stroke(), STROKE))
    return svg(body, defs)


def twist():
    defs = linear("lb", BLUE)
    # A ribbon seen from the side: its two halves swap as it turns half a revolution.
    body = ('<path d="M20,6 L44,6 C44,19 38,26 32,32 C26,26 20,19 20,6 Z" fill="#dcecff" %s/>\n'
            '<path d="M32,32 C38,38 44,45 44,58 L20,58 C20,45 26,38 32,32 Z" fill="url(#lb)" '
            '%s/>\n' % (stroke(), stroke()))
    body += ('<path d="M46,10 A16,6 0 0 1 56,24" fill="none" stroke="%s" stroke-width="3.5" '
             'stroke-linecap="round"/>\n<path d="M60,21 L55,31 L50,22 Z" fill="%s"/>\n'
             % (ORANGE[1], ORANGE[1]))
    return svg(body, defs)


def taper():
    defs = linear("lb", BLUE)
    body = ('<path d="M8,56 L56,56 L42,10 L22,10 Z" fill="url(#lb)" %s/>\n' % stroke()
            + arrow(50, 40, 40, 22, ORANGE[1], 3))
    return svg(body, defs)


def offset():
    defs = radial("b", BLUE)
    body = ('<circle cx="32" cy="32" r="28" fill="none" stroke="%s" stroke-width="2" '
            'stroke-dasharray="4,3"/>\n' % STROKE)
    body += sphere(32, 32, 17) + arrow(42, 22, 54, 10, ORANGE[1], 3)
    return svg(body, defs)


def shell():
    defs = radial("b", BLUE)
    body = ('<path d="M32,4 A28,28 0 1 1 31.99,4 Z M32,14 A18,18 0 1 0 32.01,14 Z" '
            'fill="url(#b)" fill-rule="evenodd" %s/>\n' % stroke())
    return svg(body, defs)


def metamorphosis():
    defs = radial("b", BLUE)
    body = sphere(16, 22, 12)
    body += '<rect x="38" y="36" width="22" height="22" fill="url(#b)" %s/>\n' % stroke()
    body += arrow(24, 34, 40, 46, ORANGE[1], 3)
    return svg(body, defs)


def lattice():
    """A cube of wavy gyroid-like walls: the microstructure icon."""
    defs = linear("lb", BLUE)
    body = '<rect x="4" y="4" width="56" height="56" rx="6" fill="#dcecff" %s/>\n' % stroke()
    for i, y in enumerate((14, 28, 42, 56)):
        flip = -1 if i % 2 else 1
        body += ('<path d="M4,%g C14,%g 22,%g 32,%g C42,%g 50,%g 60,%g" fill="none" '
                 'stroke="url(#lb)" stroke-width="5"/>\n'
                 % (y - 4, y - 4 - 8 * flip, y - 4 + 8 * flip, y - 4, y - 4 - 8 * flip,
                    y - 4 + 8 * flip, y - 4))
    for x in (18, 46):
        body += ('<path d="M%g,4 C%g,20 %g,44 %g,60" fill="none" stroke="%s" stroke-width="3" '
                 'opacity="0.6"/>\n' % (x, x + 8, x - 8, x, BLUE[1]))
    return svg(body, defs)


def linear_array():
    defs = radial("b", BLUE)
    return svg("".join(sphere(x, 40 - (x - 12) * 0.4, 9) for x in (12, 32, 52))
               + arrow(8, 14, 56, 14, ORANGE[1], 3), defs)


def polar_array():
    import math
    defs = radial("b", BLUE)
    body = '<circle cx="32" cy="32" r="4" fill="%s"/>\n' % ORANGE[1]
    for k in range(6):
        a = 2 * math.pi * k / 6
        body += sphere(32 + 20 * math.cos(a), 32 + 20 * math.sin(a), 8)
    return svg(body, defs)


def formula():
    """A bumpy ball behind f(x): a solid written as a formula."""
    import math
    pts = []
    for k in range(48):
        a = 2 * math.pi * k / 48
        r = 22 + 3 * math.sin(6 * a)
        pts.append("%.1f,%.1f" % (32 + r * math.cos(a), 30 + r * math.sin(a)))
    body = '<polygon points="%s" fill="url(#b)" %s/>\n' % (" ".join(pts), stroke(1.5))
    body += ('<text x="32" y="40" text-anchor="middle" font-family="serif" font-style="italic" '
             'font-size="24" font-weight="bold" fill="%s">f(x)</text>\n' % STROKE)
    return svg(body, radial("b", BLUE))


def stretch():
    """A ball drawn out into an ellipsoid along a diagonal, with arrows both ways."""
    body = ('<ellipse cx="32" cy="32" rx="26" ry="13" transform="rotate(-35 32 32)" '
            'fill="url(#b)" %s/>\n' % stroke(1.5))
    body += arrow(40, 26, 58, 13, ORANGE[1], 3) + arrow(24, 38, 6, 51, ORANGE[1], 3)
    return svg(body, radial("b", BLUE))


def solid_icon(body, defs):
    return lambda: svg(body(), defs)


ICONS = {
    "frep": frep,
    "sphere": lambda: svg(sphere(), radial("b", BLUE)),
    "box": lambda: svg(cube(6, 10, 38, 14), ""),
    "cylinder": solid_icon(cylinder_body, linear("lb", BLUE)),
    "cone": solid_icon(cone_body, linear("lb", BLUE)),
    "torus": solid_icon(torus_body, radial("b", BLUE)),
    "ellipsoid": solid_icon(ellipsoid_body, radial("b", BLUE)),
    "halfspace": solid_icon(halfspace_body, linear("lb", BLUE)),
    "translate": translate,
    "rotate": rotate,
    "scale": scale,
    "transform": transform,
    "union": lambda: venn("union"),
    "intersection": lambda: venn("intersection"),
    "difference": lambda: venn("difference"),
    "complement": complement,
    "blend_union": lambda: blend("union"),
    "blend_intersection": lambda: blend("intersection"),
    "polygonize": polygonize,
    "export": export,
    "preview": preview,
    "twist": twist,
    "taper": taper,
    "offset": offset,
    "shell": shell,
    "metamorphosis": metamorphosis,
    "gyroid": lattice,
    "linear_array": linear_array,
    "polar_array": polar_array,
    "category-array": linear_array,
    "formula": formula,
    "stretch": stretch,
    "category-formula": formula,
    # Fallbacks for node types added without their own icon, by registry category.
    "category-primitive": lambda: svg(sphere(), radial("b", BLUE)),
    "category-transform": transform,
    "category-set operation": lambda: venn("union"),
    "category-blend": lambda: blend("union"),
    "category-deformation": twist,
    "category-field operation": offset,
    "category-microstructure": lattice,
}


def main(out=OUT):
    os.makedirs(out, exist_ok=True)
    for name, make in sorted(ICONS.items()):
        text = make()
        path = os.path.join(out, name + ".svg")
        tmp = path + ".tmp"
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, path)
    print("wrote %d icons to %s" % (len(ICONS), os.path.normpath(out)))


if __name__ == "__main__":
    main(*sys.argv[1:])
