#!/usr/bin/env python3
"""Instructions per call of a library function, counted by callgrind: repeatable whatever else
the machine is doing (unlike times), so two builds can be compared on a busy machine.

Usage: instructions.py BEFORE_BUILD AFTER_BUILD
Runs each case below (a single-threaded benchmark and the isoforge function it times) under
`valgrind --tool=callgrind` for both builds and prints a table of instructions per call and their
ratio. ISOFORGE_BENCH_FIELDS must point at make_fields.py's volumes (256) for the contour cases.
"""
import os
import re
import subprocess
import sys
import tempfile

# (benchmark program, benchmark name, function whose inclusive instructions are counted). Only
# single-threaded cases: callgrind counts the calling thread's instructions, and TBB's workers'
# share of a parallel case depends on scheduling.
CASES = [
    ("bench_contour", "contour_dense/0/256/1/real_time", r"isoforge::contour_image\("),
    ("bench_contour", "contour_dense/1/256/1/real_time", r"isoforge::contour_image\("),
    ("bench_contour_sparse", "contour_vdb_cone/512/1/0/real_time", r"isoforge::contour_vdb\("),
    ("bench_implicit", "dense_icecream/256/1/real_time", r"isoforge::sample_image\("),
    ("bench_model", "modeller/0/0/1/real_time", r"isoforge::implicit_modeller\("),
    ("bench_model", "modeller/1/200/1/real_time", r"isoforge::implicit_modeller\("),
    ("bench_model", "modeller/2/64/1/real_time", r"isoforge::implicit_modeller\("),
    ("bench_model", "crossover/10000/1/real_time", r"isoforge::distance_image\("),
    ("bench_model", "attractor/real_time", r"isoforge::lorenz_attractor\("),
]


def per_call(build, program, name, function):
    """Inclusive instructions of `function` per call, from callgrind's call records."""
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "cg.out")
        subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}",
                        os.path.join(build, "verify", "bench", program),
                        f"--benchmark_filter=^{name}$", "--benchmark_min_time=0.001"],
                       check=True, capture_output=True)
        names, calls, cost = {}, 0, 0
        pattern = re.compile(function)
        lines = open(out, encoding="utf-8", errors="replace").read().splitlines()
        i = 0
        while i < len(lines):
            line = lines[i]
            m = re.match(r"c?fn=\((\d+)\)(?: (.*))?$", line)
            if m and m.group(2):
                names[m.group(1)] = m.group(2)
            if line.startswith("cfn="):
                target = names.get(re.match(r"cfn=\((\d+)\)", line).group(1), "")
                if pattern.search(target) and i + 2 < len(lines) and lines[i + 1].startswith("calls="):
                    calls += int(lines[i + 1].split("=")[1].split()[0])
                    cost += int(lines[i + 2].split()[1])
                    i += 2
            i += 1
        if calls == 0:
            raise RuntimeError(f"{program} {name}: no call of {function} recorded")
        return cost / calls


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    before, after = sys.argv[1:]
    print("| case | before (instructions / call) | after | after / before |")
    print("|---|---:|---:|---:|")
    for program, name, function in CASES:
        b = per_call(before, program, name, function)
        a = per_call(after, program, name, function)
        print(f"| {program}:{name} | {b:,.0f} | {a:,.0f} | {a / b:.4f} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
