"""The criteria table of docs/refinement.md ("Criteria and spread") from the runs of
bench/refinement.sh with adaptive variants.

Usage: python3 bench/refinement_variants.py OUT VARIANT...
  OUT: the bench's output folder (OUT=... bench/refinement.sh, STEPS=auto, every specimen and
  case, the fine runs among the VARIANTS); VARIANT: as given to the bench, e.g. adaptive or
  adaptive+strain_fraction=0.5+spread=none, one table row each in this order.

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
    is_default = strain == "bond" and spread == "family" and alpha == default_alpha
    return f"{strain}, {spread}, {alpha}" + (" (default)" if is_default else "")


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


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out, variants = sys.argv[1], sys.argv[2:]
    seconds = cpu_seconds(out)
    print("| strain, spread, alpha | glass 1 (1 MPa) | glass 2 (2 MPa) | hole, NB-NUG | hole, uniform |")
    print("| --- | --- | --- | --- | --- |")
    for variant in variants:
        name = variant.replace("+", "_").replace("=", "-")  # the bench's run_name
        cells = [cell(out, f"{case}_{name}", fine, seconds) for case, fine in CASES]
        print(f"| {label(variant)} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
