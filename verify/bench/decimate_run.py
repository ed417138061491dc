#!/usr/bin/env python3
"""Runs one command of the decimation benchmark (decimate.sh) and prints its JSON record.

Usage: decimate_run.py CASE PEER OUTPUT TARGET TIMEOUT ERRFILE -- COMMAND...
The record: the peer's own JSON line (its count and the seconds of the decimation alone) or,
for `isoforge decimate`, the count and times it prints on stderr (decimation, plus refinement
with --refine); then case, peer, output, target, status (the exit status; 124 for a timeout),
command_seconds (wall time of the whole command) and command_cpu_seconds (user + system time of
the command and its children: on a loaded machine the steadier measure of single-threaded work)."""
import json
import re
import resource
import subprocess
import sys
import time

case, peer, output, target, timeout, err = sys.argv[1:7]
command = sys.argv[sys.argv.index("--") + 1:]
before = resource.getrusage(resource.RUSAGE_CHILDREN)
t0 = time.perf_counter()
with open(err, "w") as errfile:
    try:
        p = subprocess.run(command, stdout=subprocess.PIPE, stderr=errfile, text=True,
                           timeout=float(timeout))
        status, stdout = p.returncode, p.stdout
    except subprocess.TimeoutExpired:
        status, stdout = 124, ""
wall = time.perf_counter() - t0
after = resource.getrusage(resource.RUSAGE_CHILDREN)
lines = [l for l in stdout.splitlines() if l.startswith("{")]
rec = json.loads(lines[-1]) if lines else {}
if not lines and peer.startswith("isoforge"):
    text = open(err).read()
    m = re.search(r"^wrote .*: \d+ points, (\d+) triangles .* in ([0-9.]+) s$", text, re.M)
    if m:
        rec["output_triangles"], rec["seconds"] = int(m.group(1)), float(m.group(2))
        r = re.search(r"^  refined in ([0-9.]+) s", text, re.M)
        if r:
            rec["decimate_seconds"] = rec["seconds"]
            rec["seconds"] += float(r.group(1))
rec.update({"case": case, "peer": peer, "output": output, "target": int(target), "status": status,
            "command_seconds": wall,
            "command_cpu_seconds": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)})
print(json.dumps(rec))
