#!/usr/bin/env python3
"""Kill `tear run` at pseudo-random moments and resume it; the end must equal an uninterrupted run.

docs/long-runs.md "Killed anywhere". One uninterrupted reference run, then the same run killed
KILLS times (SIGKILL, with every fourth interruption a SIGINT or SIGTERM instead, which must
stop with exit code 130 or 143 after writing a checkpoint), each time resumed with --resume.
Checked after every interruption: every frame file visible under frames/ equals the
reference's (no partial file ever shows), stats.jsonl is a prefix of the reference's. Checked at
the end: every frame, the last checkpoint and every stats line (less wall_s) are byte-identical
to the reference's, and no temporary is left behind. Exit status 0 when all holds.

  interrupt_anywhere.py --tear build/tear --scene examples/block_tear_2d.json --frames 12 \
      --kills 20 --seed 1 --work /tmp/kills [--set KEY=VALUE ...]
"""
import argparse
import json
import os
import random
import shutil
import signal
import subprocess
import sys
import time


def stats_lines(run):
    path = os.path.join(run, "stats.jsonl")
    if not os.path.exists(path):
        return []
    lines = []
    with open(path) as f:
        for line in f:
            if line.strip():
                j = json.loads(line)
                j.pop("wall_s", None)
                lines.append(j)
    return lines


def visible_files(run, sub):
    folder = os.path.join(run, sub)
    if not os.path.isdir(folder):
        return []
    return sorted(n for n in os.listdir(folder) if not n.startswith("."))


def same_bytes(a, b):
    with open(a, "rb") as fa, open(b, "rb") as fb:
        return fa.read() == fb.read()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tear", required=True)
    ap.add_argument("--scene", required=True)
    ap.add_argument("--frames", type=int, required=True)
    ap.add_argument("--kills", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--work", required=True)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--set", action="append", default=[], dest="sets")
    a = ap.parse_args()

    shutil.rmtree(a.work, ignore_errors=True)
    os.makedirs(a.work)
    ref, run = os.path.join(a.work, "ref"), os.path.join(a.work, "run")
    # Every frame in every format and a checkpoint every frame: writes are a good share of
    # the run, so that kills land in them too.
    common = ["--frames", str(a.frames), "-q", "--threads", str(a.threads),
              "--set", "output.every=1", "--set", "output.checkpoint_every=1",
              "--set", 'output.formats=["ply","bgeo","vtu"]']
    for s in a.sets:
        common += ["--set", s]

    def command(out, resume):
        return [a.tear, "run", a.scene, "-o", out] + common + (["--resume"] if resume else [])

    start = time.monotonic()
    subprocess.run(command(ref, False), check=True, stdout=subprocess.DEVNULL)
    duration = time.monotonic() - start
    reference_stats = stats_lines(ref)
    print(f"reference: {a.frames} frames in {duration:.2f} s")

    rng = random.Random(a.seed)
    failures = []
    interrupted = {"KILL": 0, "INT": 0, "TERM": 0}
    finished_early = 0
    for k in range(a.kills):
        kind = "KILL" if k % 4 != 3 else ("INT" if (k // 4) % 2 == 0 else "TERM")
        # Spread over the run: on average KILLS interruptions fit in one reference duration.
        delay = rng.uniform(0.0, 2.0 * duration / a.kills)
        resume = os.path.exists(os.path.join(run, "scene.json"))
        p = subprocess.Popen(command(run, resume), stdout=subprocess.DEVNULL,
                             stderr=subprocess.PIPE)
        time.sleep(delay)
        if p.poll() is None:
            p.send_signal(getattr(signal, "SIG" + kind))
        _, err = p.communicate()
        rc = p.returncode
        if rc == 0:
            finished_early += 1
        elif kind == "KILL" and rc == -signal.SIGKILL:
            interrupted[kind] += 1
        elif kind != "KILL" and rc in (130, 143):
            interrupted[kind] += 1
            expected = 130 if kind == "INT" else 143
            if rc != expected:
                failures.append(f"kill {k}: SIG{kind} gave exit {rc}, not {expected}")
            if b"checkpoint written" not in err:
                failures.append(f"kill {k}: SIG{kind} stop did not report its checkpoint: {err!r}")
        elif kind != "KILL" and rc in (-signal.SIGINT, -signal.SIGTERM):
            interrupted[kind] += 1  # before the handlers were installed: the default action
        else:
            failures.append(f"kill {k}: SIG{kind} after {delay:.3f} s: exit {rc}: {err!r}")
        # What a reader sees at any moment: complete frames equal to the reference's.
        for name in visible_files(run, "frames"):
            if not same_bytes(os.path.join(run, "frames", name), os.path.join(ref, "frames", name)):
                failures.append(f"kill {k}: frames/{name} differs from the reference")
        got = stats_lines(run)
        if got != reference_stats[:len(got)]:
            failures.append(f"kill {k}: stats.jsonl is not a prefix of the reference's")

    resume = os.path.exists(os.path.join(run, "scene.json"))
    final = subprocess.run(command(run, resume), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    if final.returncode != 0:
        failures.append(f"final resume: exit {final.returncode}: {final.stderr!r}")
    if visible_files(run, "frames") != visible_files(ref, "frames"):
        failures.append("final: the frame files differ from the reference's")
    for name in visible_files(ref, "frames"):
        path = os.path.join(run, "frames", name)
        if os.path.exists(path) and not same_bytes(path, os.path.join(ref, "frames", name)):
            failures.append(f"final: frames/{name} differs")
    if not same_bytes(os.path.join(run, "checkpoints", "latest.bin"),
                      os.path.join(ref, "checkpoints", "latest.bin")):
        failures.append("final: checkpoints/latest.bin differs")
    if stats_lines(run) != reference_stats:
        failures.append("final: stats.jsonl differs (wall_s aside)")
    for sub in ("", "frames", "checkpoints"):
        folder = os.path.join(run, sub)
        left = [n for n in os.listdir(folder) if n.startswith(".")]
        if left:
            failures.append(f"final: temporaries left in {folder}: {left}")

    print(f"interruptions: {interrupted['KILL']} SIGKILL, {interrupted['INT']} SIGINT, "
          f"{interrupted['TERM']} SIGTERM; {finished_early} run(s) finished before the signal")
    for f in failures:
        print("FAIL " + f)
    print(f"{'FAILED' if failures else 'passed'}: {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
