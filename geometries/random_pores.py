#!/usr/bin/env python3
"""Seeded generator of case C4: a PMMA plate with randomly placed circular pores.

Rules of [Peng, Chen, Bobaru 2023, Sec. 6]: radii uniform in [0.75, 1.5] mm;
centres at least one diameter from the plate boundary; any two pores at least
0.3 mm apart (centre distance >= r1 + r2 + 0.3 mm). Our addition: no pore
within 0.3 mm of the pre-crack (default: 2 mm from the middle of the left
edge), so that the scene's pre-crack never ends inside a pore.

The same seed and count always give the same .geo (Python's Mersenne Twister
is stable across versions). Lengths in mm, like the other geometry files.

    python3 geometries/random_pores.py --count 20 --seed 1 -o geometries/c4_20.geo
"""
import argparse
import math
import random
import sys

WIDTH, HEIGHT = 50.0, 25.0          # mm
R_MIN, R_MAX = 0.75, 1.5            # mm
GAP = 0.3                           # mm between pores
CRACK_LENGTH = 2.0                  # mm, along y = H/2 from x = 0


def distance_to_segment(px, py, ax, ay, bx, by):
    dx, dy = bx - ax, by - ay
    t = max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy)))
    return math.hypot(px - ax - t * dx, py - ay - t * dy)


def place_pores(count, seed, attempts=200000):
    rng = random.Random(seed)
    pores = []
    for _ in range(attempts):
        if len(pores) == count:
            return pores
        r = rng.uniform(R_MIN, R_MAX)
        x = rng.uniform(2 * r, WIDTH - 2 * r)
        y = rng.uniform(2 * r, HEIGHT - 2 * r)
        if distance_to_segment(x, y, 0.0, HEIGHT / 2, CRACK_LENGTH, HEIGHT / 2) < r + GAP:
            continue
        if all(math.hypot(x - px, y - py) >= r + pr + GAP for px, py, pr in pores):
            pores.append((x, y, r))
    raise SystemExit(f"random_pores.py: could not place {count} pores after {attempts} attempts "
                     f"(seed {seed}); try fewer pores")


def geo_text(pores, count, seed):
    lines = [
        f"// Case C4: PMMA plate {WIDTH:g} mm x {HEIGHT:g} mm with {count} random pores, seed {seed}.",
        "// Written by geometries/random_pores.py; rules in its header. Units: mm. OpenCASCADE kernel.",
        "// Pores (x, y, r) in mm:",
    ]
    lines += [f"//   {x:.6f} {y:.6f} {r:.6f}" for x, y, r in pores]
    lines += ['SetFactory("OpenCASCADE");', f"Rectangle(1) = {{0, 0, 0, {WIDTH:g}, {HEIGHT:g}}};"]
    for k, (x, y, r) in enumerate(pores, start=2):
        lines.append(f"Disk({k}) = {{{x:.6f}, {y:.6f}, 0, {r:.6f}, {r:.6f}}};")
    lines.append(f"BooleanDifference(1000) = {{ Surface{{1}}; Delete; }}{{ Surface{{2:{len(pores) + 1}}}; Delete; }};")
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--count", type=int, required=True, help="number of pores (e.g. 10, 20, 30)")
    parser.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    parser.add_argument("-o", "--output", required=True, help=".geo file to write")
    args = parser.parse_args()
    if args.count < 1:
        sys.exit("random_pores.py: --count must be at least 1")
    pores = place_pores(args.count, args.seed)
    text = geo_text(pores, args.count, args.seed)
    temporary = args.output + ".tmp"
    with open(temporary, "w") as f:
        f.write(text)
    import os
    os.replace(temporary, args.output)
    print(f"wrote {args.output}: {args.count} pores, seed {args.seed}")


if __name__ == "__main__":
    main()
