#!/usr/bin/env python3
"""Writes docs/accuracy-cost.md and its figures from the rows pd-validate-c1
wrote (bench/accuracy_cost.sh collects them). Standard library only: the
figures are SVG (log-log scatter plots drawn here).

Usage: accuracy_cost_report.py ALL_RUNS.csv OUT.md IMG_DIR
"""
import csv
import math
import os
import sys
import tempfile
import textwrap

GRID_COLOURS = {"uniform": "#d62728", "free": "#1f77b4", "NB-NUG": "#2ca02c"}
M_MARKERS = {3.0: "circle", 4.0: "square", 5.0: "triangle"}


def write_atomically(path, text):
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp_")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.chmod(tmp, 0o644)
    os.replace(tmp, path)


def marker(shape, x, y, colour):
    if shape == "circle":
        return f'<circle cx="{x:.1f}" cy="{y:.1f}" r="5" fill="{colour}"/>'
    if shape == "square":
        return f'<rect x="{x - 5:.1f}" y="{y - 5:.1f}" width="10" height="10" fill="{colour}"/>'
    return f'<polygon points="{x:.1f},{y - 6:.1f} {x - 6:.1f},{y + 5:.1f} {x + 6:.1f},{y + 5:.1f}" fill="{colour}"/>'


def log_ticks(lo, hi):
    ticks = []
    for e in range(math.floor(math.log10(lo)), math.ceil(math.log10(hi)) + 1):
        for m in (1, 2, 5):
            v = m * 10 ** e
            if lo <= v <= hi:
                ticks.append(v)
    return ticks


def scatter_svg(rows, xkey, xlabel, ykey, ylabel, title):
    """Log-log scatter: colour = grid, marker = m; points of one grid and m joined in order of x."""
    w, h, left, right, top, bottom = 760, 480, 80, 170, 40, 60
    xs = [float(r[xkey]) for r in rows]
    ys = [float(r[ykey]) for r in rows]
    x0, x1 = min(xs) / 1.3, max(xs) * 1.3
    y0, y1 = min(ys) / 1.3, max(ys) * 1.3
    px = lambda v: left + (math.log10(v) - math.log10(x0)) / (math.log10(x1) - math.log10(x0)) * (w - left - right)
    py = lambda v: h - bottom - (math.log10(v) - math.log10(y0)) / (math.log10(y1) - math.log10(y0)) * (h - top - bottom)
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" font-family="sans-serif" font-size="12">',
           f'<rect width="{w}" height="{h}" fill="white"/>',
           f'<text x="{left}" y="22" font-size="14">{title}</text>',
           f'<rect x="{left}" y="{top}" width="{w - left - right}" height="{h - top - bottom}" fill="none" stroke="black"/>']
    for t in log_ticks(x0, x1):
        out.append(f'<line x1="{px(t):.1f}" y1="{top}" x2="{px(t):.1f}" y2="{h - bottom}" stroke="#ddd"/>')
        out.append(f'<text x="{px(t):.1f}" y="{h - bottom + 16}" text-anchor="middle">{t:g}</text>')
    for t in log_ticks(y0, y1):
        out.append(f'<line x1="{left}" y1="{py(t):.1f}" x2="{w - right}" y2="{py(t):.1f}" stroke="#ddd"/>')
        out.append(f'<text x="{left - 6}" y="{py(t) + 4:.1f}" text-anchor="end">{t:g}</text>')
    out.append(f'<text x="{(left + w - right) / 2}" y="{h - 15}" text-anchor="middle">{xlabel}</text>')
    out.append(f'<text x="18" y="{(top + h - bottom) / 2}" text-anchor="middle" '
               f'transform="rotate(-90 18 {(top + h - bottom) / 2})">{ylabel}</text>')
    series = {}
    for r in rows:
        series.setdefault((r["grid"], float(r["horizon_factor"])), []).append(r)
    for (grid, m), points in sorted(series.items()):
        points.sort(key=lambda r: float(r[xkey]))
        colour = GRID_COLOURS.get(grid, "black")
        path = " ".join(f"{px(float(r[xkey])):.1f},{py(float(r[ykey])):.1f}" for r in points)
        out.append(f'<polyline points="{path}" fill="none" stroke="{colour}" stroke-width="1"/>')
        for r in points:
            out.append(marker(M_MARKERS.get(m, "circle"), px(float(r[xkey])), py(float(r[ykey])), colour))
    ly = top + 10
    for grid, colour in GRID_COLOURS.items():
        out.append(f'<rect x="{w - right + 15}" y="{ly - 8}" width="12" height="12" fill="{colour}"/>')
        out.append(f'<text x="{w - right + 32}" y="{ly + 2}">{grid}</text>')
        ly += 20
    for m, shape in M_MARKERS.items():
        out.append(marker(shape, w - right + 21, ly - 2, "#555"))
        out.append(f'<text x="{w - right + 32}" y="{ly + 2}">m = {m:g}</text>')
        ly += 20
    out.append("</svg>\n")
    return "\n".join(out)


LOADINGS = {
    "layers": "Loading: u_x = -/+ U on fictitious loading layers one horizon deep beyond the left and right "
              "edges (`pd-mesh --loading-layer left,right`; the particle counts include the layers), and on "
              "the FEM's edge nodes (docs/scenes.md, \"Which loading to use when\").",
    "strips": "Loading: u_x = -/+ U on the in-body strips one horizon wide at the left and right edges, "
              "which the FEM clamps too.",
}


def loading_text(rows):
    """The sentence saying how the plate was pulled; one loading per report."""
    loadings = {r.get("loading", "strips") for r in rows}
    if len(loadings) != 1:
        sys.exit(f"rows with several loadings ({', '.join(sorted(loadings))}): one report per loading")
    return LOADINGS[loadings.pop()]


def main():
    rows_path, md_path, img_dir = sys.argv[1:4]
    with open(rows_path) as f:
        rows = [r for r in csv.DictReader(f) if r["quadrature"] == "analytic" and r["surface_correction"] == "1"]
    if not rows:
        sys.exit(f"{rows_path}: no rows with analytic partial volumes and surface correction")
    for r in rows:
        r["wall_s"] = f'{float(r["setup_s"]) + float(r["solve_s"]):.6g}'
    figures = [("accuracy_cost_time.svg", "wall_s", "PD set-up + solve wall time (s)"),
               ("accuracy_cost_particles.svg", "particles", "particles")]
    for name, key, label in figures:
        svg = scatter_svg(rows, key, label, "ux_rms_rel", "RMS |u_x(PD) - u_x(FEM)| / U",
                          "C1: PD vs FEM, RMS difference of u_x")
        write_atomically(os.path.join(img_dir, name), svg)
    svg = scatter_svg(rows, "particles", "particles", "ux_near_max_rel", "max |u_x(PD) - u_x(FEM)| / U near the hole",
                      "C1: largest u_x difference within 2 delta of the hole")
    write_atomically(os.path.join(img_dir, "accuracy_cost_near_hole.svg"), svg)

    rows.sort(key=lambda r: (-float(r["spacing_mm"]), float(r["horizon_factor"]), r["grid"]))
    introduction = " ".join([
        "Generated by `bench/accuracy_cost.sh` (which runs `pd-validate-c1` and then",
        "`bench/accuracy_cost_report.py`); do not edit by hand. Case C1 and the FEM",
        "reference are described in docs/validation.md. Differences are PD minus FEM at",
        "the particles, divided by the edge displacement U = 1e-7 m; u_y after removing",
        "the mean difference (rigid translation). \"Near hole\" = particles within two",
        "horizons of the hole.", loading_text(rows),
        "Surface correction on, analytic partial areas, bond",
        "weights `distance_moment`; NCG relative residual 1e-8. Wall time = bond",
        "table and surface correction set-up plus the minimisation, on the machine",
        "that ran the script (shared, 2 cores: treat as rough).",
    ])
    lines = [
        "# Accuracy against cost: case C1",
        "",
        *textwrap.wrap(introduction, 78, break_on_hyphens=False),
        "",
        "Spacings in this run: " + ", ".join(f"{v:g} mm" for v in sorted({float(r["spacing_mm"]) for r in rows}, reverse=True))
        + "; horizon factors: " + ", ".join(f"{v:g}" for v in sorted({float(r["horizon_factor"]) for r in rows})) + ".",
        "",
        "| dx (mm) | m | delta (mm) | grid | particles | NCG iterations | wall (s) | u_x RMS | u_x max | u_x max near hole | u_y RMS | reaction PD / FEM - 1 |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        dx, m = float(r["spacing_mm"]), float(r["horizon_factor"])
        reaction = float(r["pd_reaction_N_per_m"]) / float(r["fem_reaction_N_per_m"]) - 1
        lines.append(f'| {dx:g} | {m:g} | {dx * m:g} | {r["grid"]} | {r["particles"]} | {r["ncg_iterations"]} | '
                     f'{float(r["wall_s"]):.3g} | {float(r["ux_rms_rel"]):.3g} | {float(r["ux_max_rel"]):.3g} | '
                     f'{float(r["ux_near_max_rel"]):.3g} | {float(r["uy_rms_rel"]):.3g} | {reaction:+.3g} |')
    lines += ["",
              "![RMS difference against wall time](img/accuracy_cost_time.svg)",
              "",
              "![RMS difference against particle count](img/accuracy_cost_particles.svg)",
              "",
              "![largest difference near the hole against particle count](img/accuracy_cost_near_hole.svg)",
              ""]
    write_atomically(md_path, "\n".join(lines))
    print(f"wrote {md_path} and {len(figures) + 1} figures in {img_dir}")


if __name__ == "__main__":
    main()
