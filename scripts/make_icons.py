#!/usr/bin/env python3
"""Writes the workbench's SVG icons into Mod/FRep/resources/icons.

Icons are drawn here from a few shapes so they stay consistent (64x64, one light source from
the upper left, solids in blue, operations showing their inputs in grey and the result in
blue). Run after adding a node type that deserves its own icon; a type without one falls back
to its category's icon (category-<name>.svg) and then to frep.svg.

    python3 scripts/make_icons.py
"""

import math
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


def section():
    defs = radial("b", BLUE)
    body = sphere(32, 30, 22)
    body += ('<path d="M2,42 L42,42 L62,26 L22,26 Z" fill="#ffffff" fill-opacity="0.55" %s/>\n'
             % stroke(1.5))
    body += ('<ellipse cx="32" cy="34" rx="19" ry="5.5" fill="none" stroke="%s" '
             'stroke-width="4"/>\n' % ORANGE[1])
    return svg(body, defs)


def point_sample():
    defs = radial("b", BLUE)
    body = sphere(32, 32, 24, fill="#ffffff")
    for ring, count in ((0.35, 6), (0.7, 12), (0.95, 16)):
        for k in range(count):
            a = 2 * math.pi * (k + 0.5 * ring) / count
            body += '<circle cx="%.1f" cy="%.1f" r="2.6" fill="%s"/>\n' % (
                32 + 22 * ring * math.cos(a), 32 + 22 * ring * math.sin(a), BLUE[1])
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


# -- primitives without a plain geometric body --------------------------------------------
def superellipsoid():
    """A squircle: a box with round edges."""
    return svg('<rect x="7" y="7" width="50" height="50" rx="19" fill="url(#b)" %s/>\n'
               % stroke(), radial("b", BLUE))


def sweep():
    """A ball swept along a curve: a tube with its path dashed inside."""
    path = "M8,50 C16,10 40,58 56,14"
    body = ('<path d="%s" fill="none" stroke="%s" stroke-width="17" stroke-linecap="round"/>\n'
            '<path d="%s" fill="none" stroke="%s" stroke-width="12" stroke-linecap="round"/>\n'
            '<path d="%s" fill="none" stroke="%s" stroke-width="1.5" stroke-dasharray="3,3"/>\n'
            % (path, STROKE, path, BLUE[0], path, ORANGE[1]))
    return svg(body)


def centres(points, colour=STROKE, r=2.5):
    return "".join('<circle cx="%g" cy="%g" r="%g" fill="%s"/>\n' % (x, y, r, colour)
                   for x, y in points)


def merged(circles, fill="url(#b)"):
    """Discs drawn as one solid: outlines first, then the fills over the inner lines."""
    body = "".join('<circle cx="%g" cy="%g" r="%g" fill="none" %s/>\n' % (x, y, r, stroke(3))
                   for x, y, r in circles)
    body += "".join('<circle cx="%g" cy="%g" r="%g" fill="%s"/>\n' % (x, y, r - 1.2, fill)
                    for x, y, r in circles)
    return body


def blobby():
    """Blinn's blobs: three discs melted into one, their centres marked."""
    circles = [(21, 24, 15), (43, 24, 15), (32, 43, 15), (32, 30, 10)]
    return svg(merged(circles) + centres([(21, 24), (43, 24), (32, 43)]), radial("b", BLUE))


def soft_objects():
    """Wyvill's soft objects: two blobs joined, each with its dashed radius of influence."""
    body = "".join('<circle cx="%g" cy="32" r="27" fill="none" stroke="%s" stroke-width="1.5" '
                   'stroke-dasharray="4,3"/>\n' % (x, ORANGE[1]) for x in (22, 42))
    body += merged([(22, 32, 13), (42, 32, 13), (32, 32, 8)])
    return svg(body + centres([(22, 32), (42, 32)]), radial("b", BLUE))


def convolution():
    """A field convolved from points: each point's glow fading outwards."""
    body = ""
    for x, y in ((20, 22), (44, 26), (30, 46)):
        for r, o in ((20, 0.25), (14, 0.45), (8, 0.9)):
            body += '<circle cx="%g" cy="%g" r="%g" fill="%s" opacity="%g"/>\n' % (
                x, y, r, BLUE[1], o)
    return svg(body + centres([(20, 22), (44, 26), (30, 46)], ORANGE[1], 3))


def metaballs():
    """Metaballs: a big ball and two smaller ones, merged."""
    return svg(merged([(24, 38, 18), (45, 22, 12), (48, 47, 9), (36, 34, 9)]),
               radial("b", BLUE))


def convolution_segments():
    """Convolution along line segments: a thick polyline around its skeleton."""
    path = "M8,50 L24,16 L40,44 L56,12"
    body = ('<path d="%s" fill="none" stroke="%s" stroke-width="17" stroke-linecap="round" '
            'stroke-linejoin="round"/>\n<path d="%s" fill="none" stroke="%s" stroke-width="12" '
            'stroke-linecap="round" stroke-linejoin="round"/>\n<path d="%s" fill="none" '
            'stroke="%s" stroke-width="2"/>\n' % (path, STROKE, path, BLUE[0], path, STROKE))
    return svg(body + centres([(8, 50), (24, 16), (40, 44), (56, 12)]))


def mesh_sdf():
    """A triangle mesh turned into a distance field: facets, then rings round them."""
    body = ""
    for r, o in ((29, 0.18), (23, 0.3), (17, 0.5)):
        body += '<circle cx="34" cy="34" r="%g" fill="%s" opacity="%g"/>\n' % (r, BLUE[1], o)
    pts = [(34, 20), (22, 30), (46, 30), (26, 46), (42, 46)]
    for t in ((0, 1, 2), (1, 3, 2), (3, 4, 2)):
        body += '<path d="M%s Z" fill="%s" %s/>\n' % (
            " L".join("%g,%g" % pts[i] for i in t), BLUE[0], stroke(1.5))
    return svg(body)


def vdb_grid():
    """A sparse voxel grid: a few cubes of a level set."""
    body = ""
    for x, y in ((8, 30), (26, 30), (17, 14), (35, 14)):
        body += cube(x, y, 16, 6).replace('stroke-width="2"', 'stroke-width="1.5"')
    return svg(body)


# -- operations and deformations ------------------------------------------------------------
def blend_union_icon():
    """The blend union: the fillet between the two discs marked in orange."""
    text = blend("union")
    fillet = ('<path d="M25,15 C29,16 31,19 32,22 C33,19 35,16 39,15" fill="none" stroke="%s" '
              'stroke-width="3"/>\n<path d="M25,49 C29,48 31,45 32,42 C33,45 35,48 39,49" '
              'fill="none" stroke="%s" stroke-width="3"/>\n' % (ORANGE[1], ORANGE[1]))
    return text.replace("</svg>", fillet + "</svg>")


def bounded_blend():
    """A blend acting only in a bounded region: the fillet inside a dashed box."""
    text = blend_union_icon()
    box = ('<rect x="20" y="4" width="24" height="56" fill="none" stroke="%s" stroke-width="2" '
           'stroke-dasharray="4,3"/>\n' % GREEN[1])
    return text.replace("</svg>", box + "</svg>")


def bend():
    """A bar bent into an arc, with the bending arrow."""
    body = ('<path d="M6,54 A30,30 0 0 1 58,54 L46,54 A18,18 0 0 0 18,54 Z" fill="url(#lb)" '
            '%s/>\n' % stroke())
    body += ('<path d="M14,20 A22,22 0 0 1 50,20" fill="none" stroke="%s" stroke-width="3" '
             'stroke-linecap="round"/>\n<path d="M55,14 L53,26 L44,18 Z" fill="%s"/>\n'
             % (ORANGE[1], ORANGE[1]))
    return svg(body, linear("lb", BLUE))


def deform_point():
    """A block pushed in at one point."""
    body = ('<path d="M8,16 L24,16 C28,32 36,32 40,16 L56,16 L56,56 L8,56 Z" fill="url(#lb)" '
            '%s/>\n' % stroke())
    body += arrow(32, 2, 32, 24, ORANGE[1], 3)
    return svg(body, linear("lb", BLUE, 0, 1))


def ffd():
    """The free-form deformation node: a band bent under its control polygon."""
    body = ('<path d="M6,50 Q32,18 58,50 L58,60 Q32,30 6,60 Z" fill="url(#lb)" %s/>\n'
            % stroke())
    body += ('<g fill="none" stroke="%s" stroke-width="2"><path d="M6,40 Q32,4 58,40"/>'
             '<path d="M6,40 L6,60 M58,40 L58,60"/></g>\n' % ORANGE[1])
    body += ('<g fill="%s"><circle cx="6" cy="40" r="3"/><circle cx="32" cy="22" r="3.5"/>'
             '<circle cx="58" cy="40" r="3"/></g>\n' % ORANGE[1])
    return svg(body, linear("lb", BLUE, 0, 1))


def lattice_net():
    """The Lattice command: a control net of points."""
    body = ('<g fill="none" stroke="%s" stroke-width="2.5" stroke-linejoin="round">\n'
            '<path d="M6,44 Q32,30 58,44"/><path d="M6,24 Q32,6 58,24"/>\n'
            '<path d="M6,24 L6,44 M24,16 L24,36 M40,16 L40,36 M58,24 L58,44"/>\n'
            '<path d="M6,34 Q32,18 58,34"/>\n</g>\n' % ORANGE[1])
    body += centres([(6, 24), (24, 16), (40, 16), (58, 24), (6, 44), (24, 36), (40, 36),
                     (58, 44)], STROKE, 3.5)
    return svg(body)


def deform():
    """The Deform command: a ball squeezed by the lattice round it."""
    body = ('<ellipse cx="32" cy="38" rx="22" ry="14" fill="url(#b)" %s/>\n' % stroke())
    body += ('<path d="M6,20 Q32,36 58,20 M6,56 L58,56 M6,20 L6,56 M58,20 L58,56" fill="none" '
             'stroke="%s" stroke-width="2.5"/>\n' % ORANGE[1])
    body += centres([(6, 20), (32, 28), (58, 20), (6, 56), (58, 56)], STROKE, 3.5)
    return svg(body, radial("b", BLUE))


def instancer():
    """Copies of a solid at points: a grid of small balls."""
    body = "".join(sphere(x, y, 7.5) for x in (12, 32, 52) for y in (12, 32, 52)
                   if (x, y) != (52, 12))
    body += '<circle cx="52" cy="12" r="7.5" fill="none" %s stroke-dasharray="3,2"/>\n' % stroke()
    return svg(body, radial("b", BLUE))


# -- microstructures: each surface's own pattern in a block ---------------------------------
def tile(pattern, defs=""):
    body = ('<rect x="4" y="4" width="56" height="56" rx="6" fill="#dcecff" %s/>\n' % stroke()
            + pattern)
    return svg(body, defs)


def schwarz_p():
    """Schwarz P: round holes through a block, a hole at each face's centre (a quarter of
    one at each corner of the view)."""
    holes = '<circle cx="32" cy="32" r="13" fill="#ffffff" %s/>\n' % stroke(2)
    for (cx, cy), (ax, ay), (bx, by) in (((4, 4), (4, 15), (15, 4)),
                                         ((60, 4), (49, 4), (60, 15)),
                                         ((60, 60), (60, 49), (49, 60)),
                                         ((4, 60), (15, 60), (4, 49))):
        holes += ('<path d="M%g,%g A11,11 0 0 0 %g,%g L%g,%g Z" fill="#ffffff" %s/>\n'
                  % (ax, ay, bx, by, cx, cy, stroke(2)))
    return tile('<rect x="4" y="4" width="56" height="56" rx="6" fill="url(#lb)"/>\n' + holes,
                linear("lb", BLUE))


def schwarz_d():
    """Schwarz D: two families of diagonal channels crossing, within the block."""
    def diagonal(c, rising):
        # y = x + c (falling in the view) or y = c - x, cut to the block [4, 60]^2
        xs = [x for x in (4, 60, 4 - c, 60 - c, c - 4, c - 60) if 4 <= x <= 60]
        ends = sorted({(x, x + c if not rising else c - x) for x in xs
                       if 4 <= (x + c if not rising else c - x) <= 60})
        return ends[0], ends[-1]
    pattern = ""
    for c in (-28, 0, 28):
        (x1, y1), (x2, y2) = diagonal(c, False)
        pattern += ('<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="%s" stroke-width="6" '
                    'stroke-linecap="round"/>\n' % (x1, y1, x2, y2, BLUE[1]))
    for c in (36, 64, 92):
        (x1, y1), (x2, y2) = diagonal(c, True)
        pattern += ('<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="%s" stroke-width="3.5" '
                    'opacity="0.75" stroke-linecap="round"/>\n' % (x1, y1, x2, y2, BLUE[1]))
    return tile(pattern)


def diamond():
    """Diamond: the tetrahedral network of carbon's crystal."""
    pts = [(14, 14), (32, 24), (50, 14), (32, 44), (14, 54), (50, 54)]
    body = "".join('<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="%s" stroke-width="6" '
                   'stroke-linecap="round"/>\n' % (pts[a] + pts[b] + (BLUE[1],))
                   for a, b in ((0, 1), (2, 1), (1, 3), (3, 4), (3, 5)))
    return tile(body + centres(pts, STROKE, 5))


def neovius():
    """Neovius: a block with a cross-shaped cavity and round openings."""
    body = ('<rect x="4" y="4" width="56" height="56" rx="6" fill="url(#lb)"/>\n'
            '<path d="M26,8 L38,8 L38,26 L56,26 L56,38 L38,38 L38,56 L26,56 L26,38 L8,38 '
            'L8,26 L26,26 Z" fill="#ffffff" %s/>\n' % stroke(2))
    return tile(body, linear("lb", BLUE))


def lidinoid():
    """Lidinoid: two families of waves woven through each other."""
    body = ""
    for y in (16, 32, 48):
        body += ('<path d="M4,%g C14,%g 22,%g 32,%g S50,%g 60,%g" fill="none" stroke="%s" '
                 'stroke-width="4.5"/>\n' % (y, y - 10, y + 10, y, y - 10, y, BLUE[1]))
    for x in (18, 46):
        body += ('<path d="M%g,4 C%g,18 %g,46 %g,60" fill="none" stroke="%s" stroke-width="3"/>\n'
                 % (x, x - 10, x + 10, x, ORANGE[1]))
    return tile(body)


def infill():
    """Infill: a part's skin (thick outline) with a lattice inside."""
    body = ('<path d="M6,58 L6,14 L30,6 L58,14 L58,58 Z" fill="#dcecff" stroke="%s" '
            'stroke-width="5" stroke-linejoin="round"/>\n' % BLUE[1])
    for y in (24, 36, 48):
        body += ('<path d="M10,%g C20,%g 24,%g 32,%g C40,%g 44,%g 54,%g" fill="none" '
                 'stroke="%s" stroke-width="3"/>\n' % (y, y - 7, y + 7, y, y - 7, y + 7, y,
                                                      BLUE[1]))
    return svg(body)


def strut_lattice():
    """Strut lattice: a cube cell of beams, its body diagonals meeting at the centre (BCC)."""
    front = [(8, 20), (44, 20), (44, 56), (8, 56)]
    back = [(20, 8), (56, 8), (56, 44), (20, 44)]
    edges = [(front[i], front[(i + 1) % 4]) for i in range(4)]
    edges += [(back[i], back[(i + 1) % 4]) for i in range(4)]
    edges += [(front[i], back[i]) for i in range(4)]
    body = "".join('<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="%s" stroke-width="2" '
                   'opacity="0.7"/>\n' % (a + b + (STROKE,)) for a, b in edges)
    centre = (32, 32)
    body += "".join('<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="%s" stroke-width="5.5" '
                    'stroke-linecap="round"/>\n' % (p + centre + (BLUE[1],))
                    for p in front + back)
    return svg(body + centres(front + back + [centre], STROKE, 3.5))


def voronoi_foam():
    """Voronoi foam: an irregular network of thick struts meeting by threes at round nodes."""
    nodes = [(10, 14), (28, 6), (48, 12), (58, 30), (40, 28), (22, 30), (8, 42), (26, 50),
             (46, 48), (56, 58)]
    edges = [(0, 1), (1, 2), (2, 3), (2, 4), (4, 5), (5, 0), (5, 6), (6, 7), (7, 8), (8, 4),
             (8, 9), (3, 9), (1, 4)]
    body = "".join('<line x1="%g" y1="%g" x2="%g" y2="%g" stroke="%s" stroke-width="5.5" '
                   'stroke-linecap="round"/>\n' % (nodes[a] + nodes[b] + (BLUE[1],))
                   for a, b in edges)
    return svg(body + centres(nodes, STROKE, 3.5))


# -- meshing and printing -------------------------------------------------------------------
def solid_tolerance():
    """The solid input tolerance: an arc and the facets that stand for it, the gap marked."""
    body = ('<path d="M6,52 A30,30 0 0 1 58,52" fill="none" %s/>\n'
            '<path d="M6,52 L14,30 L32,20 L50,30 L58,52" fill="none" stroke="%s" '
            'stroke-width="2.5"/>\n' % (stroke(3), ORANGE[1]))
    body += ('<path d="M32,22 L32,8 M28,12 L32,6 L36,12" fill="none" stroke="%s" stroke-width="2"'
             '/>\n' % GREEN[1])
    return svg(body + centres([(6, 52), (14, 30), (32, 20), (50, 30), (58, 52)], STROKE, 2.5))


def printability():
    body = ('<rect x="4" y="52" width="56" height="6" fill="#666666" stroke="#333333" '
            'stroke-width="2"/>\n<path d="M12,52 L12,20 L52,20 L52,52 L44,52 L44,28 L20,28 '
            'L20,52 Z" fill="url(#b)" %s/>\n<rect x="44" y="28" width="8" height="24" '
            'fill="#e03030" %s/>\n<path d="M24,8 L24,16 M20,12 L24,6 L28,12" fill="none" '
            'stroke="%s" stroke-width="3" stroke-linecap="round" stroke-linejoin="round"/>\n'
            % (stroke(), stroke(), GREEN[1]))
    return svg(body, radial("b", BLUE))


def repair():
    body = ('<path d="M8,40 L26,10 L46,22 L52,44 L30,56 Z" fill="url(#b)" %s/>\n'
            '<path d="M26,10 L30,56 M8,40 L46,22" fill="none" %s/>\n'
            '<path d="M34,30 L44,26 L40,36 Z" fill="#ffffff" stroke="#b02020" stroke-width="2" '
            'stroke-linejoin="round"/>\n<path d="M42,46 L58,30 L62,34 L46,50 Z" fill="#c8c8c8" '
            'stroke="#333333" stroke-width="2" stroke-linejoin="round"/>\n<path d="M54,26 L60,20 '
            'L62,22 L58,30" fill="#c8c8c8" stroke="#333333" stroke-width="2" '
            'stroke-linejoin="round"/>\n' % (stroke(), stroke(1.5)))
    return svg(body, radial("b", BLUE))


# -- hsplines: a surface of B-spline patches (tan) with its control points -----------------
TAN, TAN_EDGE, CV_GREEN, CV_RED = "#d9b56a", "#7a5a1a", "#1a8a3a", "#d01c1c"


def hspline_sheet(cv_colour=CV_RED, detail=True, extra=""):
    body = ('<path d="M4,46 C16,30 28,54 40,38 C48,28 54,34 60,30 L60,50 C54,54 48,48 40,58 '
            'C28,74 16,50 4,62 Z" fill="%s" stroke="%s" stroke-width="2"/>\n' % (TAN, TAN_EDGE))
    body += ('<path d="M4,30 L22,22 L40,24 L60,16" fill="none" stroke="%s" stroke-width="1.5"/>\n'
             % STROKE)
    body += centres([(4, 30), (22, 22), (40, 24), (60, 16)], CV_GREEN, 3.5)
    if detail:
        body += ('<path d="M26,40 L34,36 L42,38" fill="none" stroke="%s" stroke-width="1.5"/>\n'
                 % STROKE + centres([(26, 40), (34, 36), (42, 38)], cv_colour, 2.8))
    return svg(body + extra)


def hspline_zero():
    body = ('<path d="M4,40 C20,34 44,34 60,40 L60,56 C44,50 20,50 4,56 Z" fill="%s" '
            'stroke="%s" stroke-width="2"/>\n<path d="M32,8 L32,30" stroke="%s" stroke-width="3"/>'
            '<path d="M24,22 L32,32 L40,22" fill="none" stroke="%s" stroke-width="3"/>\n'
            % (TAN, TAN_EDGE, CV_RED, CV_RED))
    return svg(body + centres([(32, 36)], CV_GREEN, 4))


def hspline_unrefine():
    return hspline_sheet(detail=False, extra='<path d="M20,8 L44,32 M44,8 L20,32" stroke="%s" '
                         'stroke-width="4"/>\n' % CV_RED)


def hspline_plane():
    """A new hspline plane: a flat sheet and its grid of control points."""
    body = ('<path d="M4,48 L20,20 L60,20 L44,48 Z" fill="%s" stroke="%s" stroke-width="2"/>\n'
            % (TAN, TAN_EDGE))
    pts = [(4 + 13.3 * i + 8 * j, 48 - 14 * j) for i in range(4) for j in range(3)]
    return svg(body + centres(pts, CV_GREEN, 3) + plus_badge())


def hspline_cylinder():
    """A new hspline cylinder: a tube of patches and its rings of control points."""
    body = ('<path d="M12,14 L12,50 A20,7 0 0 0 52,50 L52,14 Z" fill="%s" stroke="%s" '
            'stroke-width="2"/>\n<ellipse cx="32" cy="14" rx="20" ry="7" fill="#f0dcae" '
            'stroke="%s" stroke-width="2"/>\n' % (TAN, TAN_EDGE, TAN_EDGE))
    pts = [(12, 32), (22, 37), (32, 39), (42, 37), (52, 32), (12, 50), (32, 57), (52, 50)]
    return svg(body + centres(pts, CV_GREEN, 3) + plus_badge())


def hspline_torus():
    """A new hspline torus."""
    body = ('<ellipse cx="32" cy="34" rx="28" ry="17" fill="%s" stroke="%s" stroke-width="2"/>\n'
            '<ellipse cx="32" cy="31" rx="12" ry="5.5" fill="#ffffff" stroke="%s" '
            'stroke-width="2"/>\n' % (TAN, TAN_EDGE, TAN_EDGE))
    pts = [(6, 34), (16, 45), (32, 50), (48, 45), (58, 34), (32, 19)]
    return svg(body + centres(pts, CV_GREEN, 3) + plus_badge())


def hspline_from_face():
    """An hspline from a B-spline face: a solid's face lifted off as a sheet."""
    body = cube(4, 22, 30, 10, GREY).replace('fill="#e4e4e4"', 'fill="#f2f2f2"', 1)
    body += ('<path d="M30,14 C40,4 52,10 60,4 L60,24 C52,30 40,24 30,34 Z" fill="%s" '
             'stroke="%s" stroke-width="2"/>\n' % (TAN, TAN_EDGE))
    return svg(body + arrow(22, 30, 38, 20, ORANGE[1], 3))


def hspline_solid():
    """To solid: a closed hspline filled."""
    body = ('<ellipse cx="32" cy="34" rx="28" ry="17" fill="url(#b)" %s/>\n'
            '<ellipse cx="32" cy="31" rx="12" ry="5.5" fill="#ffffff" %s/>\n'
            % (stroke(), stroke()))
    return svg(body + centres([(6, 34), (32, 51), (58, 34), (32, 17)], CV_GREEN, 3),
               radial("b", BLUE))


def hspline_envelope():
    """Envelope: a bent tube carried by two skeleton segments meeting at a joint."""
    body = ('<path d="M6,22 L30,22 C44,22 50,30 50,44 L50,60 L34,60 L34,44 C34,40 32,38 28,38 '
            'L6,38 Z" fill="%s" stroke="%s" stroke-width="2"/>\n' % (TAN, TAN_EDGE))
    body += ('<path d="M4,30 L42,30 L42,62" fill="none" stroke="#333333" stroke-width="3" '
             'stroke-linecap="round" stroke-linejoin="round"/>\n')
    return svg(body + centres([(4, 30), (42, 30), (42, 62)], CV_RED, 4))


def hspline_attach():
    """Attach: a tube standing on a sheet, joined around a ring of the sheet's CVs."""
    body = ('<path d="M2,46 L18,32 L62,32 L46,46 Z" fill="%s" stroke="%s" stroke-width="2"/>\n'
            % (TAN, TAN_EDGE))
    body += ('<path d="M22,38 C22,30 24,26 26,12 L42,12 C44,26 46,30 46,38 Z" fill="#e8c987" '
             'stroke="%s" stroke-width="2"/>\n<ellipse cx="34" cy="12" rx="8" ry="3" '
             'fill="#f0dcae" stroke="%s" stroke-width="2"/>\n' % (TAN_EDGE, TAN_EDGE))
    return svg(body + centres([(22, 38), (34, 42), (46, 38), (34, 34)], CV_GREEN, 3))


def hspline_struts():
    """Struts along an hspline: a curved sheet filled with a zig-zag of struts."""
    body = ('<path d="M4,30 C20,14 44,14 60,30 L60,48 C44,32 20,32 4,48 Z" fill="%s" '
            'stroke="%s" stroke-width="2"/>\n' % (TAN, TAN_EDGE))
    body += ('<path d="M8,40 L16,26 L24,35 L32,22 L40,35 L48,26 L56,40" fill="none" '
             'stroke="#333333" stroke-width="3" stroke-linecap="round" '
             'stroke-linejoin="round"/>\n')
    return svg(body + centres([(8, 40), (16, 26), (24, 35), (32, 22), (40, 35), (48, 26),
                               (56, 40)], CV_RED, 3))


def file_page(extra):
    return ('<path d="M14,4 L42,4 L52,14 L52,60 L14,60 Z" fill="#ffffff" %s/>\n'
            '<path d="M42,4 L42,14 L52,14" fill="none" %s/>\n'
            '<text x="33" y="56" text-anchor="middle" font-family="sans-serif" font-size="12" '
            'font-weight="bold" fill="%s">.hs</text>\n' % (stroke(), stroke(), TAN_EDGE) + extra)


def hspline_import():
    return svg(file_page('<path d="M18,38 C24,28 32,44 40,32" fill="none" stroke="%s" '
                         'stroke-width="4"/>\n' % TAN_EDGE) + arrow(2, 24, 24, 24, GREEN[1], 4))


def hspline_export():
    return svg(file_page('<path d="M18,38 C24,28 32,44 40,32" fill="none" stroke="%s" '
                         'stroke-width="4"/>\n' % TAN_EDGE) + arrow(40, 24, 62, 24, GREEN[1], 4))


def plus_badge():
    """A green plus in the lower right: the command makes a new object."""
    return ('<circle cx="52" cy="52" r="10" fill="%s" stroke="#ffffff" stroke-width="2"/>\n'
            '<path d="M52,46 L52,58 M46,52 L58,52" stroke="#ffffff" stroke-width="3"/>\n'
            % GREEN[1])


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
    "blend_union": blend_union_icon,
    "blend_intersection": lambda: blend("intersection"),
    "polygonize": polygonize,
    "section": section,
    "point_sample": point_sample,
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
    "superellipsoid": superellipsoid,
    "sweep": sweep,
    "blobby": blobby,
    "soft_objects": soft_objects,
    "convolution": convolution,
    "metaballs": metaballs,
    "convolution_segments": convolution_segments,
    "mesh_sdf": mesh_sdf,
    "vdb_grid": vdb_grid,
    "bounded_blend": bounded_blend,
    "bend": bend,
    "deform_point": deform_point,
    "ffd": ffd,
    "instancer": instancer,
    "schwarz_p": schwarz_p,
    "schwarz_d": schwarz_d,
    "diamond": diamond,
    "neovius": neovius,
    "lidinoid": lidinoid,
    "infill": infill,
    "strut_lattice": strut_lattice,
    "voronoi_foam": voronoi_foam,
    "lattice": lattice_net,
    "deform": deform,
    "solid_tolerance": solid_tolerance,
    "printability": printability,
    "repair": repair,
    "hspline": hspline_sheet,
    "hspline_refine": lambda: hspline_sheet("#1c3ad0"),
    "hspline_zero": hspline_zero,
    "hspline_unrefine": hspline_unrefine,
    "hspline_plane": hspline_plane,
    "hspline_cylinder": hspline_cylinder,
    "hspline_torus": hspline_torus,
    "hspline_from_face": hspline_from_face,
    "hspline_solid": hspline_solid,
    "hspline_import": hspline_import,
    "hspline_export": hspline_export,
    "hspline_envelope": hspline_envelope,
    "hspline_attach": hspline_attach,
    "hspline_struts": hspline_struts,
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
