"""The comparison table of bench/c3_side_by_side.sh: variants (model, grid) side by side on C3.

Reads, for each case X in {a, b, c} and each variant whose run exists (WORK/c3X_VARIANT/post/
summary.json; VARIANT is pmb, osb, uniform_pmb, ...), WORK/c3X_VARIANT/ (pd-solve's summary.json)
and WORK/c3X_VARIANT/post/ (pd-post's summary.json, crack_tips.csv, pore_trapping.csv,
branching_events.csv), and WORK/times.txt (bench/lib.sh `timed`), and prints Markdown: one table
per case, one column per variant, and the damage pictures next to each other.

Usage: python3 bench/c3_side_by_side_report.py WORK DX   (DX as given to the bench script, e.g. 0.125mm)
"""
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from summary_json import find, load  # noqa: E402

CASES = ("a", "b", "c")
PLATE_WIDTH_M = 0.050   # the plate of geometries/c3*_pores.geo
PRECRACK_TIP_X_M = 0.002  # the long pre-crack of geometries/c3*_long.toml


def rows(path):
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]


def read_times(path):
    """NAME -> (wall [s], peak [kB], CPU [s] or None) from bench/lib.sh `timed` lines."""
    times = {}
    if os.path.exists(path):
        for line in open(path):
            if line.startswith("Command"):  # GNU time's note on a killed run
                continue
            name, wall, peak_kb, *cpu = line.split()  # older lines have no CPU times
            # A run resumed from its checkpoint has one line per part: their sum.
            wall_before, peak_before, cpu_before = times.get(name, (0.0, 0, 0.0))
            cpu_s = sum(map(float, cpu)) if cpu and cpu_before is not None else None
            times[name] = (wall_before + float(wall), max(peak_before, int(peak_kb)),
                           None if cpu_s is None else cpu_before + cpu_s)
    return times


def us(seconds):
    return f"{seconds * 1e6:.1f}"


class Run:
    """One solver run and its pd-post output."""

    def __init__(self, work, case, model, times):
        self.dir = os.path.join(work, f"c3{case}_{model}")
        grid, _, name = model.rpartition("_")
        self.label = f"{name.upper()}, {grid or 'NB-NUG'}"
        self.post = os.path.join(self.dir, "post")
        self.exists = os.path.exists(os.path.join(self.post, "summary.json"))
        if not self.exists:
            return
        self.solver = load(os.path.join(self.dir, "summary.json")) if os.path.exists(
            os.path.join(self.dir, "summary.json")) else {}
        self.postsum = load(os.path.join(self.post, "summary.json"))
        self.tips = rows(os.path.join(self.post, "crack_tips.csv"))
        self.pores = rows(os.path.join(self.post, "pore_trapping.csv"))
        self.events = rows(os.path.join(self.post, "branching_events.csv"))
        self.wall = times.get(f"solve_c3{case}_{model}", (None, None))[0]

    def first_growth_time(self):
        # crack_tips.csv starts one step before initiation, at the pre-crack's tip (docs/post.md).
        return min(float(r["time_s"]) for r in self.tips) + self.postsum["time_step_s"]

    def reached_right_edge(self):
        reason = self.solver.get("stop_reason", "") or ""
        return reason.startswith("stop condition")

    def pore_visits(self):
        """Pore index -> list of (pore x [m], pore y [m], text), by entry time. The text is the
        trapping time [us]; for a branch that never restarted from the pore, the time from entry
        to its branching "(branches)", if it branched afterwards, else "ends there"."""
        branchings = {}
        for e in self.events:
            branchings.setdefault(int(e["parent"]), []).append(float(e["time_s"]))
        visits = {}
        for r in sorted(self.pores, key=lambda r: float(r["enter_time_s"])):
            enter, trapping = float(r["enter_time_s"]), float(r["trapping_time_s"] or -1)
            if trapping >= 0:
                text = f"{trapping * 1e6:.2f}"
            else:
                later = [t for t in branchings.get(int(r["branch"]), []) if t >= enter]
                text = f"{(min(later) - enter) * 1e6:.2f} (branches)" if later else "ends there"
            visits.setdefault(int(r["pore"]), []).append((float(r["x_m"]), float(r["y_m"]), text))
        return visits


def row(label, cells):
    return f"| {label} | " + " | ".join(cells) + " |"


def variants(work, case):
    """The variants of CASE run in WORK, NB-NUG first, PMB before OSB."""
    prefix = f"c3{case}_"
    found = [d[len(prefix):] for d in os.listdir(work)
             if d.startswith(prefix) and os.path.isdir(os.path.join(work, d))]
    order = {"pmb": 0, "osb": 1}
    return sorted(found, key=lambda v: ("_" in v, v.rpartition("_")[0], order.get(v.rpartition("_")[2], 2)))


def case_table(case, runs):
    present = [m for m in runs if runs[m].exists]
    labels = [runs[m].label for m in present]
    out = [f"### C3-{case.upper()}", "", "| | " + " | ".join(labels) + " |",
           "| --- |" + " --- |" * len(present)]
    r = {m: runs[m] for m in present}
    out.append(row("model Poisson ratio (c_R from it)", [f"{find(r[m].postsum, 'poisson_ratio'):.4g}" for m in present]))
    out.append(row("c_R [m/s]", [f"{r[m].postsum['rayleigh_speed_m_per_s']:.1f}" for m in present]))
    out.append(row("critical stretch s0", [f"{find(r[m].solver, 'critical_stretch'):.5f}" for m in present]))
    out.append(row("time step [us] (automatic)", [f"{r[m].postsum['time_step_s'] * 1e6:.4f}" for m in present]))
    out.append(row("speed window [steps]", [str(r[m].postsum["window"]["steps"]) for m in present]))
    out.append(row("first crack growth [us]", [us(r[m].first_growth_time()) for m in present]))

    def end_cell(run):
        end = run.postsum["run"]["end_time_s"]
        if not run.postsum["run"]["complete"]:
            return f"incomplete, at {us(end)}"
        if run.reached_right_edge():
            return f"{us(end)} (crack at the right edge)"
        return f"{us(end)} (end time)"
    out.append(row("run ends at [us]", [end_cell(r[m]) for m in present]))

    def average_speed(run):
        # From initiation to the right edge along the mid-line, trapping included.
        if not (run.postsum["run"]["complete"] and run.reached_right_edge()):
            return "-"
        t = run.postsum["run"]["end_time_s"] - run.first_growth_time()
        v = (PLATE_WIDTH_M - PRECRACK_TIP_X_M) / t
        return f"{v:.0f} m/s = {v / run.postsum['rayleigh_speed_m_per_s']:.2f}"
    out.append(row("(W - a0) / (end - first growth), / c_R", [average_speed(r[m]) for m in present]))
    def ratio(value):  # null in summary.json: no whole speed window
        return "-" if value is None else f"{value:.2f}"
    out.append(row("mean speed / c_R (growth windows, all branches)",
                   [ratio(r[m].postsum['mean_speed_over_rayleigh']) for m in present]))
    out.append(row("peak speed / c_R", [ratio(r[m].postsum['max_speed_over_rayleigh']) for m in present]))
    out.append(row("branches / branching events",
                   [f"{len(r[m].postsum['branches'])} / {len(r[m].events)}" for m in present]))

    def events_cell(run):
        if not run.events:
            return "none"
        xs = [float(e["x_m"]) * 1e3 for e in run.events]
        first = min(run.events, key=lambda e: float(e["time_s"]))
        return (f"first at {us(float(first['time_s']))} us, ({float(first['x_m']) * 1e3:.1f}, "
                f"{float(first['y_m']) * 1e3:.1f}) mm; x = {min(xs):.1f} to {max(xs):.1f} mm")
    out.append(row("branching", [events_cell(r[m]) for m in present]))
    visits = {m: r[m].pore_visits() for m in present}
    pores = sorted(set().union(*[set(v) for v in visits.values()]),
                   key=lambda p: next(v[p][0][:2] for v in visits.values() if p in v))
    for p in pores:
        x, y = next(v[p][0][:2] for v in visits.values() if p in v)

        def cell(m):
            if p not in visits[m]:
                return "no visit recorded"
            return "; ".join(text for _, _, text in visits[m][p])
        out.append(row(f"trapping time at pore ({x * 1e3:.1f}, {y * 1e3:.1f}) mm [us]", [cell(m) for m in present]))
    out.append(row("solve wall time [min]",
                   ["-" if r[m].wall is None else f"{r[m].wall / 60:.1f}" for m in present]))
    out.append("")
    pictures = " | ".join(f"![](c3{case}_{m}/post/damage_final.png)" for m in present)
    out += ["| " + " | ".join(labels) + " |", "|" + " --- |" * len(present),
            f"| {pictures} |", ""]
    return out


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    work, dx = sys.argv[1], sys.argv[2]
    times = read_times(os.path.join(work, "times.txt"))
    lines = [f"## C3, long pre-crack, dx = {dx}: PMB, OSB (nu = 0.35), per grid", ""]
    for case in CASES:
        runs = {m: Run(work, case, m, times) for m in variants(work, case)}
        if any(run.exists for run in runs.values()):
            lines += case_table(case, runs)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
