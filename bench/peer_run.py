"""One timed `clothsim run` for the peer scripts (peer_blender.py, peer_dress.py, peer_chart.py): wall and CPU
seconds of the whole process (loading and writing frames included, as Blender's bake includes its set-up) and its
--stats."""
import json
import resource
import subprocess
import sys
import time


def run_clothsim_status(clothsim, xml, threads, stats):
    """As run_clothsim_timed, but a run that diverges (exit 3) or warns is returned, not raised: the exit code and
    stderr (clothsim's warnings and errors, docs/errors.md) come back with the times and the --stats."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall0 = time.perf_counter()
    proc = subprocess.run([clothsim, "run", xml, "--threads", str(threads), "--stats", stats, "--quiet"],
                          stderr=subprocess.PIPE, text=True)
    wall = time.perf_counter() - wall0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    with open(stats) as f:
        st = json.load(f)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return proc.returncode, wall, cpu, st, proc.stderr


def run_clothsim_timed(clothsim, xml, threads, stats):
    rc, wall, cpu, st, err = run_clothsim_status(clothsim, xml, threads, stats)
    sys.stderr.write(err)  # warnings still reach the terminal, as before
    if rc != 0:
        raise RuntimeError(f"clothsim run {xml} exited {rc}: {err.strip()}")
    return wall, cpu, st
