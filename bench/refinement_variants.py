"""The criteria table of docs/refinement.md ("Criteria and spread") from the runs of
bench/refinement.sh with adaptive variants.

Usage: python3 bench/refinement_variants.py OUT VARIANT...
       python3 bench/refinement_variants.py --steps "auto 1.18e-7 ..." OUT VARIANT...
  OUT: the bench's output folder (OUT=... bench/refinement.sh, STEPS=auto, every specimen and
  case, the fine runs among the VARIANTS); VARIANT: as given to the bench, e.g. adaptive or
  adaptive+strain_fraction=0.5+spread=none, one table row each in this order.
  --steps: the bench's STEPS of OUT; the table then counts, per variant and case, the steps at
  which the adaptive run keeps the fine run of the same step's pattern (see `kept`).
  A case whose runs are not in OUT (SPECIMENS=hole, say) gets "-" cells.

Each cell: particles at the end / one-thread CPU s (user + system, OUT/times.txt) / the first
branching's distance from the fine run's (glass; the hole's fine runs have none: the adaptive
run's first branching time, or none) / bonds broken by splits / mm^2 (particles) of damage
outside the fine run's band (pd-post --reference). The row's label names the criterion, the
spread and alpha, the scene's defaults filled in.
"""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from summary_json import load  # noqa: E402

CASES = [("glass_case1", "glass_case1_fine"), ("glass_case2", "glass_case2_fine"),
         ("hole_nbnug", None), ("hole_uniform", None)]


def first_branching(run):
    with open(os.path.join(run, "post", "branching_events.csv")) as f:
        events = list(csv.DictReader(f))
    if not events:
        return None
    e = events[0]
    return float(e["time_s"]), float(e["x_m"]), float(e["y_m"])


def cpu_seconds(out):
    seconds = {}
    with open(os.path.join(out, "times.txt")) as f:
        for line in f:
            name, _wall, _peak, user, system = line.split()
            seconds[name] = float(user) + float(system)
    return seconds


def label(variant):
    """'bond, family, 0.4 (default)' from 'adaptive' and the keys after its '+'."""
    keys = dict(k.split("=", 1) for k in variant.split("+")[1:])
    strain = keys.get("strain", "bond")
    default_alpha = "0.4" if strain == "bond" else "0.5"
    alpha = keys.get("strain_fraction", default_alpha)
    spread = keys.get("spread", "family")
    if spread not in ("family", "none"):
        spread = f"{spread} horizon"
    others = {k: v for k, v in keys.items() if k not in ("strain", "strain_fraction", "spread")}
    is_default = strain == "bond" and spread == "family" and alpha == default_alpha and not others
    return (f"{strain}, {spread}, {alpha}" + "".join(f", {k} {v}" for k, v in others.items()) +
            (" (default)" if is_default else ""))


def cell(out, name, fine, seconds):
    run = os.path.join(out, name)
    summary = load(os.path.join(run, "summary.json"))
    comparison = load(os.path.join(run, "post", "summary.json"))["comparison"]
    refinement = summary.get("refinement", {})
    branching = first_branching(run)
    if branching is None:
        where = "none"
    elif fine:
        reference = first_branching(os.path.join(out, fine))
        where = (f"{math.hypot(branching[1] - reference[1], branching[2] - reference[2]) * 1e3:.1f} mm"
                 if reference else f"{branching[0] * 1e6:.1f} us")
    else:
        where = f"{branching[0] * 1e6:.1f} us"
    return (f"{refinement.get('particles_end')} / {seconds.get(name, float('nan')):.1f} / {where} / "
            f"{refinement.get('bonds_broken_by_splits')} / "
            f"{comparison['area_outside_band_m2'] * 1e6:.0f} ({comparison['damaged_outside_band']})")


def kept(out, name, fine):
    """Whether run `name` keeps the pattern of the fine run `fine` (or of no branching, the hole's
    fine runs: `fine` None) and the damage outside that run's band in mm^2 and the bonds broken by
    splits. Kept: the first branching within 2 mm of the fine run's (none if it has none), at most
    2 mm^2 outside its band (the uniform hole grid's own fine run has up to 2 mm^2 outside the
    NB-NUG fine run's band) and no bond broken by a split."""
    run = os.path.join(out, name)
    comparison = load(os.path.join(run, "post", "summary.json"))["comparison"]
    bonds = load(os.path.join(run, "summary.json")).get("refinement", {}).get("bonds_broken_by_splits", 0)
    area = comparison["area_outside_band_m2"] * 1e6
    branching = first_branching(run)
    reference = first_branching(os.path.join(out, fine)) if fine else None
    if branching is None or reference is None:
        same_branching = branching is None and reference is None
    else:
        same_branching = math.hypot(branching[1] - reference[1], branching[2] - reference[2]) <= 2e-3
    return same_branching and area <= 2 and bonds == 0, area, bonds


def step_cell(out, name, fine, steps):
    """'k/n, X mm^2, B' over the steps: kept at k of n steps, mean damage outside, bonds broken."""
    results = []
    for step in steps:
        suffix = "" if step == "auto" else f"_dt{step}"
        results.append(kept(out, name + suffix, fine + suffix if fine else None))
    n = len(results)
    return (f"{sum(r[0] for r in results)}/{n}, {sum(r[1] for r in results) / n:.1f} mm^2, "
            f"{sum(r[2] for r in results)}")


def main():
    args = sys.argv[1:]
    steps = None
    if args[:1] == ["--steps"] and len(args) > 1:
        steps, args = args[1].split(), args[2:]
    if len(args) < 2:
        sys.exit(__doc__)
    out, variants = args[0], args[1:]
    seconds = None if steps else cpu_seconds(out)
    print("| strain, spread, alpha | glass 1 (1 MPa) | glass 2 (2 MPa) | hole, NB-NUG | hole, uniform |")
    print("| --- | --- | --- | --- | --- |")
    for variant in variants:
        name = variant.replace("+", "_").replace("=", "-")  # the bench's run_name
        cells = []
        for case, fine in CASES:
            if not os.path.isfile(os.path.join(out, f"{case}_{name}", "summary.json")):
                cells.append("-")  # this case was not run
            elif steps:
                cells.append(step_cell(out, f"{case}_{name}", fine, steps))
            else:
                cells.append(cell(out, f"{case}_{name}", fine, seconds))
        print(f"| {label(variant)} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
