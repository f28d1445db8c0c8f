#!/usr/bin/env python3
"""Writes examples/helix.json, the reference model 'helix', exactly:

20 spheres of radius 0.3, f_i = 0.3 - |p - c_i|, centred at c_i = (cos t, sin t, t/4 - 3 pi/4)
with t = i 6 pi / 19 (i = 0..19), chained by Pasko's blend union on the max union
(R-function alpha = 1): F_1 = f_1, F_i = max(F_{i-1}, f_i) + 0.5 / (1 + (F_{i-1}/0.3)^2 +
(f_i/0.3)^2). The registry's blend_union folds from the left, which is this chain.
Bounding box [-2.75, 2.75]^3. Coordinates are written with 17 significant digits (doubles
round-trip exactly).

    python3 examples/make_helix.py
"""

import json
import math
import os

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "helix.json")


def main():
    spheres = []
    for i in range(20):
        t = i * 6 * math.pi / 19
        center = [float("%.17g" % v) for v in (math.cos(t), math.sin(t),
                                                t / 4 - 3 * math.pi / 4)]
        spheres.append({"type": "sphere", "params": {"center": center, "radius": 0.3}})
    model = {
        "frepcad": 1,
        "description": "Reference model 'helix': 20 spheres of radius 0.3 along a helix "
                       "(c_i = (cos t, sin t, t/4 - 3 pi/4), t = i 6 pi/19), chained by "
                       "Pasko's blend union on the max union (alpha = 1, a0 = 0.5, "
                       "a1 = a2 = 0.3). One connected chain, volume about 14.39.",
        "root": {"type": "blend_union",
                 "params": {"a0": 0.5, "a1": 0.3, "a2": 0.3, "alpha": 1},
                 "inputs": spheres},
        "export": {"bbox": [-2.75, -2.75, -2.75, 2.75, 2.75, 2.75], "resolution": 0.015625},
    }
    tmp = OUT + ".tmp"
    with open(tmp, "w") as f:
        json.dump(model, f, indent=1)
        f.write("\n")
    os.replace(tmp, OUT)
    print("wrote", OUT)


if __name__ == "__main__":
    main()
