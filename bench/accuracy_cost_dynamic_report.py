#!/usr/bin/env python3
"""The dynamic part of docs/accuracy-cost.md and its figures, from the runs of
bench/accuracy_cost_dynamic.sh: C3-A and C3-B with the long pre-crack at several horizons
and horizon factors, each quantity of the crack against the run's cost.

Reads WORK/delta_*mm_m_*/ (one bench/c3_side_by_side.sh folder per horizon and m, with the
runs c3a_pmb and c3b_pmb), replaces everything from the marker line on in OUT.md (the C1 part
before it is bench/accuracy_cost_report.py's) and writes IMG_DIR/accuracy_cost_c3_*.svg.

Usage: accuracy_cost_dynamic_report.py WORK OUT.md IMG_DIR
"""
import glob
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from accuracy_cost_report import DYNAMIC_MARKER, scatter_svg, write_atomically  # noqa: E402
from c3_side_by_side_report import PRECRACK_TIP_X_M, Run, read_times  # noqa: E402
from summary_json import find  # noqa: E402

CASE_COLOURS = {"C3-A": "#1f77b4", "C3-B": "#ff7f0e",
                "C3-A, boxes dx/2": "#17becf", "C3-B, boxes dx/2": "#d62728"}
# The runs of one folder: the NB-NUG plate as meshed, and its boxes at dx / 2
# with dual horizons (bench/c3_side_by_side.sh's grid boxes2).
VARIANTS = {"pmb": "", "boxes2_pmb": ", boxes dx/2"}


def measure(folder, case, variant="pmb"):
    """The row of one run, or None if it has no results yet."""
    run = Run(folder, case, variant, read_times(os.path.join(folder, "times.txt")))
    if not run.exists:
        return None
    wall, _, cpu = read_times(os.path.join(folder, "times.txt")).get(f"solve_c3{case}_{variant}",
                                                                    (None, None, None))
    first = run.first_growth_time()
    visits = sorted((v for p in run.pore_visits().values() for v in p), key=lambda v: v[0])
    trapping = [float(text) for p in run.pore_visits().values() for _, _, text in p
                if re.fullmatch(r"[0-9.]+", text)]
    first_pore = min(run.pores, key=lambda r: float(r["enter_time_s"])) if run.pores else None
    speed = None
    if first_pore is not None:
        # Mean speed from initiation to the first pore's ring, along x (the mid-line).
        speed = (float(first_pore["x_m"]) - float(first_pore["radius_m"]) - PRECRACK_TIP_X_M) / (
            float(first_pore["enter_time_s"]) - first)
    complete = run.postsum["run"]["complete"] and run.reached_right_edge()
    spacing = find(run.solver, "spacing_m")
    horizon = find(run.solver, "horizon_m")
    return {
        "case": case, "grid": f"C3-{case.upper()}{VARIANTS[variant]}", "boxes": VARIANTS[variant][2:] or "as meshed",
        "horizon_factor": f"{horizon / spacing:.6g}",
        "spacing_mm": spacing * 1e3, "delta_mm": horizon * 1e3,
        "particles": find(run.solver, "particles"), "steps": find(run.solver, "steps"),
        "wall_s": wall, "cpu_s": cpu,
        "initiation_us": first * 1e6,
        "speed_over_cr": None if speed is None else speed / run.postsum["rayleigh_speed_m_per_s"],
        "mean_trapping_us": sum(trapping) / len(trapping) if trapping else None,
        "pores_trapped": len(trapping), "pore_visits": len(visits),
        "separation_us": run.postsum["run"]["end_time_s"] * 1e6 if complete else None,
        "branches": len(run.postsum["branches"]),
    }


def observed_order(rows, key):
    """Order p of q(delta) = q* + C delta^p from three horizons at one m (Richardson), if the
    differences shrink monotonically; else None."""
    if len(rows) != 3 or any(r[key] is None for r in rows):
        return None
    rows = sorted(rows, key=lambda r: -r["delta_mm"])
    (d1, q1), (d2, q2), (d3, q3) = [(r["delta_mm"], r[key]) for r in rows]
    if (q1 - q2) * (q2 - q3) <= 0 or abs(q2 - q3) >= abs(q1 - q2):
        return None
    ratio = (q1 - q2) / (q2 - q3)
    lo, hi = 0.05, 8.0  # bisection on (d1^p - d2^p) / (d2^p - d3^p) = ratio, increasing in p
    f = lambda p: (d1 ** p - d2 ** p) / (d2 ** p - d3 ** p) - ratio
    if f(lo) * f(hi) > 0:
        return None
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(lo) * f(mid) > 0 else (lo, mid)
    return 0.5 * (lo + hi)


def cell(value, fmt):
    return "-" if value is None else format(value, fmt)


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    work, md_path, img_dir = sys.argv[1:4]
    rows = []
    for folder in sorted(glob.glob(os.path.join(work, "delta_*mm_m_*"))):
        for case in ("a", "b"):
            for variant in VARIANTS:
                row = measure(folder, case, variant)
                if row is not None:
                    rows.append(row)
    if not rows:
        sys.exit(f"{work}: no finished runs (expected delta_*mm_m_*/c3a_pmb/post/summary.json)")
    rows.sort(key=lambda r: (r["case"], -r["delta_mm"], float(r["horizon_factor"]), r["boxes"] != "as meshed"))
    # Cost: CPU time (user + system of pd-solve) where recorded, which the load of a shared
    # machine distorts less than wall time.
    cost_key = "cpu_s" if all(r["cpu_s"] for r in rows) else "wall_s"
    cost_label = "pd-solve CPU time (s)" if cost_key == "cpu_s" else "pd-solve wall time (s)"
    figures = [("initiation_us", "first crack growth (us)", "initiation"),
               ("speed_over_cr", "speed to the first pore / c_R", "speed"),
               ("mean_trapping_us", "mean trapping time per pore (us)", "trapping"),
               ("separation_us", "crack at the right edge (us)", "separation")]
    names = []
    for key, label, name in figures:
        plotted = [r for r in rows if r[key] is not None and r[cost_key]]
        if not plotted:
            continue
        svg = scatter_svg(plotted, cost_key, cost_label, key, label, f"C3, long pre-crack: {label}",
                          colours=CASE_COLOURS, log_y=False)
        write_atomically(os.path.join(img_dir, f"accuracy_cost_c3_{name}.svg"), svg)
        names.append((name, label))

    lines = [DYNAMIC_MARKER, "",
             "# Accuracy against cost: dynamic fracture, C3-A and C3-B", "",
             "Generated by `bench/accuracy_cost_dynamic.sh` (which runs `bench/c3_side_by_side.sh` per",
             "horizon and then `bench/accuracy_cost_dynamic_report.py`); do not edit by hand. The",
             "perforated PMMA plates with the long (2 mm) pre-crack, `geometries/c3a_long.toml` and",
             "`c3b_long.toml` as written (bond-based PMB, surface correction, NB-NUG grid with boxes",
             "of side 2 mm, automatic time step, stop when the crack reaches the right edge), at",
             "horizons delta = 0.24, 0.20, 0.16 mm with m = 4 and at m = 3, 4, 5 with delta = 0.5 mm.",
             "There is no exact answer to compare with: the finest run is the reference the others",
             "move towards, and where three horizons at one m change a quantity monotonically with",
             "shrinking differences, its observed order p (q = q* + C delta^p) is given.",
             "Quantities from pd-post (docs/post.md): first crack growth; the mean crack speed from",
             "there to the ring of the first pore, along x, over the Rayleigh speed; the trapping",
             "time averaged over the pores where the crack restarted; the time the crack reached",
             "the right edge; the number of branches. Cost: " + cost_label + " of the solve on the",
             "machine that ran the script (2 threads). On a shared machine both scatter by several",
             "times from run to run, and under load OpenMP's spinning waits count as CPU time too",
             "(docs/performance.md, \"Fewer parallel regions per step\"): compare costs within one",
             "quiet sitting only.",
             "Rows with boxes \"dx/2\" are the same plate with the boxes round the pores meshed at half",
             "the spacing (`pd-mesh --box-spacing`, horizons m dx / 2 there) and run with dual horizons",
             "(`model.dual_horizon = true`, surface correction off): what finer particles at the pores",
             "change and cost (`RUNS=\"0.5:4:boxes2 ...\"`).",
             ""]
    # The study's runs (bench/accuracy_cost_dynamic.sh's default RUNS) that have no results.
    expected = [(0.5, "3"), (0.5, "4"), (0.5, "5"), (0.24, "4"), (0.2, "4"), (0.16, "4")]
    for case in ("a", "b"):
        done = {(round(r["delta_mm"], 2), r["horizon_factor"]) for r in rows
                if r["case"] == case and r["boxes"] == "as meshed"}
        missing = [f"delta = {d:g} mm, m = {m}" for d, m in expected if (d, m) not in done]
        if missing:
            lines += [f"C3-{case.upper()}: not run to the end yet: " + "; ".join(missing) + ".", ""]
    # How busy the machine was (WORK/load.txt, bench/accuracy_cost_dynamic.sh's samples).
    loads = os.path.join(work, "load.txt")
    if os.path.exists(loads):
        one_minute = sorted(float(line.split()[1]) for line in open(loads) if len(line.split()) == 4)
        if one_minute:
            lines += [f"The machine's 1-minute load average during the study (2 cores; {len(one_minute)} samples "
                      f"30 s apart): median {one_minute[len(one_minute) // 2]:.2f}, at most {one_minute[-1]:.2f}. "
                      "Above 2, other work shared the cores and the costs grow with it.", ""]
    # Notes the person who ran the study left beside its runs (WORK/notes.md),
    # e.g. a run whose cost is partial because it was resumed from a checkpoint.
    notes = os.path.join(work, "notes.md")
    if os.path.exists(notes):
        lines += [open(notes).read().strip(), ""]
    for case in ("a", "b"):
        case_rows = [r for r in rows if r["case"] == case]
        if not case_rows:
            continue
        lines += [f"## C3-{case.upper()}", "",
                  "| delta (mm) | m | dx (mm) | boxes | particles | steps | CPU (s) | wall (s) | first growth (us) | "
                  "speed to pore 1 / c_R | mean trapping (us), pores | right edge (us) | branches |",
                  "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"]
        for r in case_rows:
            lines.append(
                f'| {r["delta_mm"]:.4g} | {r["horizon_factor"]} | {r["spacing_mm"]:.4g} | {r["boxes"]} | {r["particles"]} | '
                f'{r["steps"]} | {cell(r["cpu_s"], ".0f")} | {cell(r["wall_s"], ".0f")} | '
                f'{r["initiation_us"]:.1f} | {cell(r["speed_over_cr"], ".2f")} | '
                f'{cell(r["mean_trapping_us"], ".2f")}, {r["pores_trapped"]} | {cell(r["separation_us"], ".1f")} | '
                f'{r["branches"]} |')
        m4 = [r for r in case_rows if r["horizon_factor"] == "4" and r["delta_mm"] < 0.3 and r["boxes"] == "as meshed"]
        orders = []
        for key, label, _ in figures:
            p = observed_order(m4, key)
            orders.append(f"{label}: " + ("no monotone convergence" if p is None else f"p = {p:.2f}"))
        if len(m4) == 3:
            lines += ["", "Observed order over delta = 0.24, 0.20, 0.16 mm (m = 4): " + "; ".join(orders) + "."]
        lines.append("")
    for name, label in names:
        lines += [f"![{label} against cost](img/accuracy_cost_c3_{name}.svg)", ""]

    old = open(md_path).read() if os.path.exists(md_path) else ""
    static = old[:old.index(DYNAMIC_MARKER)] if DYNAMIC_MARKER in old else (old + "\n" if old else "")
    write_atomically(md_path, static + "\n".join(lines))
    print(f"wrote the dynamic part of {md_path} ({len(rows)} runs) and {len(names)} figures in {img_dir}")


if __name__ == "__main__":
    main()
