"""The cost of adaptive refinement in instructions (docs/refinement.md, "Cost"), from the runs of
`CALLGRIND=1 bench/refinement.sh` (one thread, under callgrind; OUT/instructions.txt).

Usage: python3 bench/refinement_instructions.py OUT [VARIANT...]
  VARIANT: the adaptive variants to report (default: adaptive), as given to the bench.

One row per case and adaptive variant: the coarse, fine and adaptive runs' instructions [1e9],
the adaptive run's ratios to the coarse and the fine run against the issue's targets (at most
1.3x the coarse run, at most 0.35x the fine one), and the shares of the adaptive run spent in the
refinement events (of which the refined sets' set-up) and in the time steps. Instruction counts
do not depend on the machine's load; they stand for the work, not the wall time.
"""
import os
import sys

TARGET_COARSE, TARGET_FINE = 1.3, 0.35


def read(out):
    runs = {}
    with open(os.path.join(out, "instructions.txt")) as f:
        for line in f:
            name, total, events, setup, steps = line.split()
            runs[name] = (int(total), int(events), int(setup), int(steps))  # the last line of a name wins
    return runs


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out, variants = sys.argv[1], sys.argv[2:] or ["adaptive"]
    runs = read(out)
    print("| case | run | coarse 1e9 | fine 1e9 | adaptive 1e9 | / coarse (target 1.3) | / fine (target 0.35) "
          "| events (set-up) | steps |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    cases = sorted({name.rsplit("_", 1)[0] for name in runs if name.endswith("_coarse")})
    for case in cases:
        coarse, fine = runs.get(f"{case}_coarse"), runs.get(f"{case}_fine")
        for variant in variants:
            name = f"{case}_{variant.replace('+', '_').replace('=', '-')}"  # the bench's run_name
            adaptive = runs.get(name)
            if not (coarse and fine and adaptive):
                print(f"| {case} | {variant} | missing runs in {out}/instructions.txt | | | | | | |")
                continue
            total, events, setup, steps = adaptive
            print(f"| {case} | {variant} | {coarse[0] / 1e9:.2f} | {fine[0] / 1e9:.2f} | {total / 1e9:.2f} | "
                  f"{total / coarse[0]:.1f}x | {total / fine[0]:.2f}x | {events / total:.0%} "
                  f"({setup / total:.0%}) | {steps / total:.0%} |")


if __name__ == "__main__":
    main()
