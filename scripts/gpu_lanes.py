#!/usr/bin/python3
"""How busy a GPU's threads are, from the lives of a CPU run's particles (docs/model.md, "The GPU engine").

A warp's 32 threads step together. One thread a particle (the plain CUDA loop): a warp runs as long as the longest
life among its 32 particles, so its threads are busy sum(c) / (32 max(c)) of the time, c a particle's collisions.
Threads that take the next particle when their own ends (the engine's lanes): a launch of L particles over T threads
runs until its last particles end, so the threads are busy sum(c) / (T makespan), the makespan found by handing the
particles in id order to the thread free first (the lives a thread holds in a launch, L / T, taken from the engine's
launch and the device's threads). Their ratio is what the lanes gain if a collision costs the same in both loops;
it leaves out the registers (and so the occupancy) each loop needs, the branches that split a warp within a
collision, and the lanes' draws when a particle starts.

For each of bench_gpu's scenes, runs ``rotleak simulate`` with escape records (the CPU's engine; the lives are the
same on any engine), then prints a Markdown table and writes it as CSV.

Usage: scripts/gpu_lanes.py BUILD_DIR OUT.csv [PARTICLES (default 1000000)] [THREADS_ON_DEVICE (default 101376:
an H100's 132 multiprocessors x 768)] [LAUNCH (default 268435456: the engine's 2^16 blocks of 4096)]
"""
import csv
import heapq
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from table_rates import write_csv  # noqa: E402  (a temporary name, then a rename)

SCENES = [
    ("s_L = 0", ["leak.start=0", "leak.omega=0"]),
    ("omega = 2/3", ["leak.omega=2/3"]),
    ("quick-start", []),
]


def lives(build, sets, particles, work):
    """Each particle's collisions (escape records in id order) of the quick-start scene with `sets`."""
    out = os.path.join(work, "run")
    scene = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "scenes", "quickstart.toml")
    cmd = [os.path.join(build, "rotleak"), "simulate", scene, "--particles", str(particles),
           "--set", "observe.escapes=true", "--no-progress", "--force", "--out", out]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(out, "escapes.csv")) as f:
        return [int(r["collisions"]) for r in csv.DictReader(f)]


def plain_busy(c):
    """One thread a particle: warps of 32 consecutive ids, each as long as its longest life."""
    slots = sum(32 * max(c[k:k + 32]) for k in range(0, len(c), 32))
    return sum(c) / slots


def lanes_busy(c, threads):
    """Threads taking particles in id order whenever their own ends: busy share until the last one ends."""
    free = [0] * threads
    heapq.heapify(free)
    for life in c:
        heapq.heappush(free, heapq.heappop(free) + life)
    return sum(c) / (threads * max(free))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    build, out_csv = sys.argv[1], sys.argv[2]
    particles = int(sys.argv[3]) if len(sys.argv) > 3 else 1000000
    device_threads = int(sys.argv[4]) if len(sys.argv) > 4 else 101376
    launch = int(sys.argv[5]) if len(sys.argv) > 5 else 268435456
    # the sample keeps the launch's lives a thread: L / T
    threads = max(1, round(particles * device_threads / launch))
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for name, sets in SCENES:
            c = lives(build, sets, particles, work)
            plain, lane = plain_busy(c), lanes_busy(c, threads)
            rows.append({"scene": name, "particles": len(c), "mean_collisions": round(sum(c) / len(c), 2),
                         "max_collisions": max(c), "plain_busy": round(plain, 4),
                         "lanes_busy": round(lane, 4), "lives_a_thread": round(len(c) / threads, 1),
                         "predicted_ratio": round(lane / plain, 2)})
    print("| scene | mean collisions | most | plain loop busy | lanes busy | predicted engine / plain |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['scene']} | {r['mean_collisions']} | {r['max_collisions']} | {r['plain_busy']:.1%} | "
              f"{r['lanes_busy']:.1%} | {r['predicted_ratio']} |")
    write_csv(out_csv, rows)


if __name__ == "__main__":
    main()
