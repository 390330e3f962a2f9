"""The scaling model of docs/scaling.md: step time, parallel efficiency and memory per node of a
dynamic C3-kind run (a 2:1 plate, PMB or OSB, m = 4) on P nodes with slabs along the long axis.

Inputs (docs/scaling.md, "Inputs"): directed bonds per particle, the measured per-core rates of the
lattice sweep on one process and under MPI, cores per node, the network's latency and bandwidth, ghost
bytes, reductions per step, memory per particle. Prints the table as Markdown rows.
Usage: python3 bench/scaling_model.py [R_MPI] [MODEL] [HIDING]   (R_MPI: the per-core rate of PMB on a
slab [1/s]; MODEL: pmb (default) or osb: the lattice sweep at 0.58 of PMB's rate (docs/performance.md,
"OSB") and a second exchange per step, 8 bytes per ghost (theta / m); HIDING: the share of a step's
compute that runs while the ghost messages travel (docs/solver.md, "What overlaps what": the general
pairs of two owned particles and the owned cells' scatter), split evenly between the exchanges)

The messages of an exchange (latency and bytes) are hidden behind that compute as far as it lasts;
the reductions are not overlapped.
"""
import math
import sys

bonds_per_particle = 67          # b
rate_one_process = 1.32e9        # r_lat, directed bond evaluations / s per core, one process
rate_mpi = float(sys.argv[1]) if len(sys.argv) > 1 else rate_one_process  # r_mpi, per core on a slab
model = sys.argv[2] if len(sys.argv) > 2 else "pmb"
hiding = float(sys.argv[3]) if len(sys.argv) > 3 else 0.0
if model not in ("pmb", "osb"):
    sys.exit(f"bench/scaling_model.py: MODEL = {model}: expected pmb or osb")
cores = 64                       # c, per node
latency = 2e-6                   # s per message
bandwidth = 10e9                 # bytes / s per node
m = 4                            # delta / dx
ghost_bytes = 16                 # per ghost and step: ux, uy
exchanges = 1                    # ghost exchanges per step, 2 latencies each (a message each way)
if model == "osb":
    # OSB against PMB on the lattice, back to back (docs/performance.md, "OSB"); theta / m after the pre-pass.
    rate_one_process *= 0.58
    rate_mpi *= 0.58
    ghost_bytes += 8
    exchanges = 2
reductions = 4                   # per step, each log2(P) latencies
# bytes per particle in the time loop on the lattice path: 320 MB for C3-A's 772,295 particles at
# dx = 0.04 mm (docs/performance.md, "Where the memory goes"), set-up not included
memory_per_particle = 320e6 / 772295
print("| N | nodes | slab [particles] | halo sent per step [MB] | t_c [ms] | t_x [ms] | t_x not hidden [ms] "
      "| eff, not overlapped | eff | memory [GB] |")
print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
for n in (1e7, 1e8, 1e9):
    height = math.sqrt(n / 2)
    for nodes in (1, 16, 64, 256, 1024):
        slab = 2 * height / nodes
        if slab < 2 * m:
            print(f"| {n:.0e} | {nodes} | {slab:.2g} | (slab thinner than two horizons) | | | | | | |")
            continue
        rate = rate_one_process if nodes == 1 else rate_mpi
        t_c = n * bonds_per_particle / (nodes * cores * rate)
        halo = 0 if nodes == 1 else 2 * m * height * ghost_bytes
        messages = 0 if nodes == 1 else 2 * exchanges * latency + halo / bandwidth
        reductions_time = 0 if nodes == 1 else reductions * math.log2(nodes) * latency
        t_x = messages + reductions_time
        # Each exchange's messages behind its share of the hidden compute.
        shown = exchanges * max(0.0, messages / exchanges - hiding * t_c / exchanges) + reductions_time
        memory = n / nodes * memory_per_particle / 1e9
        print(f"| {n:.0e} | {nodes} | {slab:.0f} | {halo / 1e6:.2g} | {1e3 * t_c:.3g} | {1e3 * t_x:.2g} "
              f"| {1e3 * shown:.2g} | {t_c / (t_c + t_x):.2f} | {t_c / (t_c + shown):.2f} | {memory:.2g} |")
