"""One timed `clothsim run` for the peer scripts (peer_blender.py, peer_dress.py): wall and CPU seconds of the
whole process (loading and writing frames included, as Blender's bake includes its set-up) and its --stats."""
import json
import resource
import subprocess
import time


def run_clothsim_timed(clothsim, xml, threads, stats):
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall0 = time.perf_counter()
    subprocess.run([clothsim, "run", xml, "--threads", str(threads), "--stats", stats, "--quiet"], check=True)
    wall = time.perf_counter() - wall0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    with open(stats) as f:
        st = json.load(f)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, st
