#!/usr/bin/env python3
"""Writes docs/accuracy-cost.md and its figures from the rows pd-validate-c1
wrote (bench/accuracy_cost.sh collects them). Standard library only: the
figures are SVG (log-log scatter plots drawn here).

Usage: accuracy_cost_report.py ALL_RUNS.csv OUT.md IMG_DIR
       accuracy_cost_report.py --box-spacing BOX_RUNS.csv OUT.md IMG_DIR
The second form writes only the section of OUT.md between the box-spacing
markers (finer NB-NUG boxes, bench/accuracy_cost.sh box_spacing_rows); the
first keeps that section as it is.
"""
import csv
import math
import os
import sys
import tempfile

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


def scatter_svg(rows, xkey, xlabel, ykey, ylabel, title, colours=GRID_COLOURS):
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
        colour = colours.get(grid, "black")
        path = " ".join(f"{px(float(r[xkey])):.1f},{py(float(r[ykey])):.1f}" for r in points)
        out.append(f'<polyline points="{path}" fill="none" stroke="{colour}" stroke-width="1"/>')
        for r in points:
            out.append(marker(M_MARKERS.get(m, "circle"), px(float(r[xkey])), py(float(r[ykey])), colour))
    ly = top + 10
    for grid, colour in colours.items():
        out.append(f'<rect x="{w - right + 15}" y="{ly - 8}" width="12" height="12" fill="{colour}"/>')
        out.append(f'<text x="{w - right + 32}" y="{ly + 2}">{grid}</text>')
        ly += 20
    for m, shape in M_MARKERS.items():
        out.append(marker(shape, w - right + 21, ly - 2, "#555"))
        out.append(f'<text x="{w - right + 32}" y="{ly + 2}">m = {m:g}</text>')
        ly += 20
    out.append("</svg>\n")
    return "\n".join(out)


# ---- Finer NB-NUG boxes (pd-mesh --box-spacing) -------------------------------
BOX_BEGIN = "<!-- box-spacing rows: begin (bench/accuracy_cost.sh box_spacing_rows) -->"
BOX_END = "<!-- box-spacing rows: end -->"
BOX_COLOURS = {"uniform": "#d62728", "NB-NUG": "#2ca02c", "NB-NUG box dx/2": "#9467bd", "NB-NUG box dx/4": "#ff7f0e"}


def box_section_of(md_path):
    """The box-spacing section of an existing OUT.md, markers included ("" if none)."""
    if not os.path.exists(md_path):
        return ""
    text = open(md_path).read()
    begin, end = text.find(BOX_BEGIN), text.find(BOX_END)
    return text[begin:end + len(BOX_END)] + "\n" if begin >= 0 and end > begin else ""


def finest_spacing(r):
    """dx of the squares, or of the boxes for "NB-NUG ... box dx/F" rows [mm]."""
    dx = float(r["spacing_mm"])
    return dx / int(r["grid"].split("box dx/")[1].split()[0]) if "box dx/" in r["grid"] else dx


def box_spacing_section(rows_path, md_path, img_dir):
    with open(rows_path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{rows_path}: no rows")
    for r in rows:
        r["wall_s"] = f'{float(r["setup_s"]) + float(r["solve_s"]):.6g}'
        r["finest_mm"] = f"{finest_spacing(r):g}"
        # Every row of this study is dual-horizon without surface correction: the section says so once.
        r["grid"] = r["grid"].replace(" no-sc", "").replace(" dual-horizon", "")
    svg = scatter_svg(rows, "wall_s", "PD set-up + solve wall time (s)", "ux_near_max_rel",
                      "max |u_x(PD) - u_x(FEM)| / U near the hole",
                      "C1, finer boxes: largest u_x difference within 2 delta of the hole", BOX_COLOURS)
    write_atomically(os.path.join(img_dir, "accuracy_cost_boxes.svg"), svg)
    rows.sort(key=lambda r: (-float(r["finest_mm"]), r["grid"], -float(r["spacing_mm"])))
    lines = [
        BOX_BEGIN,
        "",
        "## Finer NB-NUG boxes (`pd-mesh --box-spacing`)",
        "",
        "C1 with the NB-NUG box around the hole meshed at dx / 2 and dx / 4",
        "(`NB-NUG box dx/F`), against the uniform grid of the same finest spacing",
        "and the NB-NUG grid of constant spacing dx; m = 3 (box cells m x their",
        "box's spacing). Every row here is dual-horizon PD (theory.md Sec. 6) solved",
        "by the linear solution of theory.md Sec. 6.5, without surface correction",
        "(dual horizons have none), so compare these rows with each other, not with",
        "the table above. FEM element size 0.1 mm at the hole; \"near hole\" = within",
        "1 mm of it for every row (the same particles' region whatever the grid).",
        "Wall time as above.",
        "",
        "| finest spacing (mm) | dx of the squares (mm) | grid | particles | directed bonds | CG iterations | wall (s) | u_x RMS | u_x max near hole | u_y RMS | reaction PD / FEM - 1 |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        reaction = float(r["pd_reaction_N_per_m"]) / float(r["fem_reaction_N_per_m"]) - 1
        lines.append(f'| {r["finest_mm"]} | {float(r["spacing_mm"]):g} | {r["grid"]} | {r["particles"]} | '
                     f'{r["directed_bonds"]} | {r["ncg_iterations"]} | {float(r["wall_s"]):.3g} | '
                     f'{float(r["ux_rms_rel"]):.3g} | {float(r["ux_near_max_rel"]):.3g} | '
                     f'{float(r["uy_rms_rel"]):.3g} | {reaction:+.3g} |')
    lines += ["", "![finer boxes: largest difference near the hole against wall time](img/accuracy_cost_boxes.svg)",
              "", BOX_END]
    section = "\n".join(lines) + "\n"
    text = open(md_path).read() if os.path.exists(md_path) else ""
    old = box_section_of(md_path)
    text = text.replace(old, section) if old else text.rstrip("\n") + "\n\n" + section
    write_atomically(md_path, text)
    print(f"wrote the box-spacing section of {md_path} and {img_dir}/accuracy_cost_boxes.svg")
# ---- end of finer NB-NUG boxes -------------------------------------------------


def main():
    if sys.argv[1] == "--box-spacing":
        box_spacing_section(*sys.argv[2:5])
        return
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
    lines = [
        "# Accuracy against cost: case C1",
        "",
        "Generated by `bench/accuracy_cost.sh` (which runs `pd-validate-c1` and then",
        "`bench/accuracy_cost_report.py`); do not edit by hand. Case C1 and the FEM",
        "reference are described in docs/validation.md. Differences are PD minus FEM at",
        "the particles, divided by the edge displacement U = 1e-7 m; u_y after removing",
        "the mean difference (rigid translation). \"Near hole\" = particles within two",
        "horizons of the hole. Surface correction on, analytic partial areas, bond",
        "weights `distance_moment`; NCG relative residual 1e-8. Wall time = bond",
        "table and surface correction set-up plus the minimisation, on the machine",
        "that ran the script (shared, 2 cores: treat as rough).",
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
    box_section = box_section_of(md_path)  # written by the --box-spacing form; kept
    write_atomically(md_path, "\n".join(lines) + ("\n" + box_section if box_section else ""))
    print(f"wrote {md_path} and {len(figures) + 1} figures in {img_dir}")


if __name__ == "__main__":
    main()
