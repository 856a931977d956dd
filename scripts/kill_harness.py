#!/usr/bin/env python3
"""Crash safety (issue 26): each writer is killed (SIGKILL) at random moments, KILLS times, and
after each kill the file it writes must open and check whole (`lacet info`: a scene's checksum,
every tile of a pyramid), holding either what it held before or the new result, never a mixture;
an interrupted pyramid build or update, run again, must give the tiles of an uninterrupted one.

  scripts/kill_harness.py [--kills N] [--landed] [--seed S] [--writers save,import,import_parts,pyramid_build,pyramid_update]
                          [--lacet build/lacet] [--work DIR] [--json]

Writers (each over a small scene, so that a kill lands anywhere in a run of a fraction of a second):
  save            lacet synth --out over an existing scene (the atomic save: temporary file, rename)
  import          lacet import --dem-storage lod over an existing scene (a DEM tree written out of
                  core beside the output, then the scene saved)
  import_parts    the same with the vectors out of core (--vector-part-level 2: a spill file beside
                  the output, the scene written a part at a time)
  pyramid_build   lacet pyramid build of a scene with no pyramid yet, then run again to the end
  pyramid_update  lacet pyramid update of a pyramid whose scene changed, then run again to the end
  pyramid_mpi     lacet pyramid build --shards under mpirun -np 2, one rank killed (not by default:
                  it needs Open MPI and a lacet built with LACET_MPI)
A kill's moment is uniform between the start and the median time of three uninterrupted runs; a
run that ends before it counts as a trial, checked the same way. With --landed, trials go on until
KILLS of them were killed before their end (at most 4 x KILLS trials).
After all the kills, the folder must hold no temporary file (a writer killed leaves its temporary,
the next run of a writer removes it).

Prints a table (or JSON) of kills, results and failures per writer; exits 1 when any file did not
open whole, held a mixture, or a resumed pyramid differed. The import's vectors are the test
inputs' good.geojson and its DEM is made here (gdal_create); nothing is read from ../shared.
"""
import argparse
import hashlib
import json
import os
import random
import shutil
import signal
import sqlite3
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
VECTORS = os.path.join(ROOT, "tests", "data", "vectors", "good.geojson")


def run(cmd, cwd, check=True):
    r = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if check and r.returncode != 0:
        sys.exit("kill_harness: %s failed (%d):\n%s%s" % (" ".join(cmd), r.returncode, r.stderr, r.stdout))
    return r


def scene_checksum(path):
    """The checksum a scene file stores (its content's identity); None when unreadable."""
    try:
        con = sqlite3.connect("file:%s?mode=ro" % path, uri=True)
        try:
            return con.execute("SELECT value FROM lacet_meta WHERE key = 'checksum'").fetchone()[0]
        finally:
            con.close()
    except Exception:
        return None


def pyramid_digest(path):
    """A digest of every tile and quad digest of a pyramid, in a fixed order."""
    con = sqlite3.connect("file:%s?mode=ro" % path, uri=True)
    try:
        h = hashlib.sha256()
        tables = [r[0] for r in con.execute("SELECT table_name FROM gpkg_contents WHERE data_type IN ('tiles', '2d-gridded-coverage') ORDER BY table_name")]
        for t in tables:
            for z, x, y, data in con.execute('SELECT zoom_level, tile_column, tile_row, tile_data FROM "%s" ORDER BY 1, 2, 3' % t):
                h.update(("%s/%d/%d/%d:" % (t, z, x, y)).encode())
                h.update(data)
        for row in con.execute("SELECT level, quad_x, quad_y, digest FROM lacet_pyramid_quads ORDER BY 1, 2, 3"):
            h.update(repr(row).encode())
        return h.hexdigest()
    finally:
        con.close()


def whole(lacet, path, cwd):
    """Whether `lacet info` reads the file whole (it checks the checksum or every tile)."""
    return run([lacet, "info", path], cwd, check=False).returncode == 0


def temporaries(folder):
    return sorted(f for f in os.listdir(folder) if f.endswith(".tmp") or f.endswith("-journal") or f.endswith("-wal"))


class Writer:
    def __init__(self, name, lacet, folder):
        self.name, self.lacet, self.folder = name, lacet, folder
        self.stats = {"kills": 0, "killed_before_done": 0, "finished_before_kill": 0, "old_whole": 0, "new_whole": 0,
                      "absent": 0, "not_whole": 0, "mixture": 0, "resumed_equal": 0, "resumed_different": 0}
        self.failures = []

    def timed(self, cmd):
        t0 = time.monotonic()
        run(cmd, self.folder)
        return time.monotonic() - t0

    def kill_once(self, cmd, delay):
        p = subprocess.Popen(cmd, cwd=self.folder, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            p.wait(timeout=delay)
            self.stats["finished_before_kill"] += 1
        except subprocess.TimeoutExpired:
            p.send_signal(signal.SIGKILL)
            p.wait()
            self.stats["killed_before_done"] += 1
        self.stats["kills"] += 1

    def fail(self, why):
        self.failures.append(why)


class SceneWriter(Writer):
    """synth --out or import over an existing scene: after a kill, the old scene or the new, whole."""

    def __init__(self, name, lacet, folder, make_new):
        super().__init__(name, lacet, folder)
        self.path = os.path.join(folder, "scene.gpkg")
        self.make_new = make_new
        run([lacet, "synth", "--curves", "300", "--seed", "1", "--out", "old.gpkg"], folder)
        self.old = scene_checksum(os.path.join(folder, "old.gpkg"))
        shutil.copy(os.path.join(folder, "old.gpkg"), self.path)
        times = []
        for _ in range(3):
            times.append(self.timed(make_new))
            self.new = scene_checksum(self.path)
            shutil.copy(os.path.join(folder, "old.gpkg"), self.path)
        self.median_s = statistics.median(times)

    def trial(self, rng, i):
        shutil.copy(os.path.join(self.folder, "old.gpkg"), self.path)
        self.kill_once(self.make_new, rng.uniform(0.0, self.median_s))
        if not whole(self.lacet, "scene.gpkg", self.folder):
            self.stats["not_whole"] += 1
            self.fail("kill %d: scene.gpkg does not open whole" % i)
            return
        c = scene_checksum(self.path)
        if c == self.old:
            self.stats["old_whole"] += 1
        elif c == self.new:
            self.stats["new_whole"] += 1
        else:
            self.stats["mixture"] += 1
            self.fail("kill %d: scene.gpkg opens whole but is neither the old scene nor the new" % i)


class PyramidWriter(Writer):
    """pyramid build (no pyramid before) or update (of the old scene's pyramid): after a kill the
    pyramid is absent, the old one or a whole file, and a run to the end gives the uninterrupted tiles."""

    def __init__(self, name, lacet, folder):
        super().__init__(name, lacet, folder)
        self.pyramid = os.path.join(folder, "scene.pyramid.gpkg")
        run([lacet, "synth", "--curves", "1500", "--seed", "1", "--out", "a.gpkg"], folder)
        run([lacet, "synth", "--curves", "1500", "--seed", "2", "--out", "b.gpkg"], folder)
        run([lacet, "pyramid", "build", "a.gpkg", "--out", "a.pyramid.gpkg"], folder)
        run([lacet, "pyramid", "build", "b.gpkg", "--out", "b.pyramid.gpkg"], folder)
        self.expected = pyramid_digest(os.path.join(folder, "b.pyramid.gpkg"))
        self.old = pyramid_digest(os.path.join(folder, "a.pyramid.gpkg")) if name == "pyramid_update" else None
        self.cmd = [lacet, "pyramid", name.split("_")[1], "scene.gpkg"]
        times = []
        for _ in range(3):
            self.reset()
            times.append(self.timed(self.cmd))
        self.median_s = statistics.median(times)

    def reset(self):
        shutil.copy(os.path.join(self.folder, "b.gpkg"), os.path.join(self.folder, "scene.gpkg"))
        for f in os.listdir(self.folder):
            if f.startswith("scene.pyramid.gpkg"):
                os.remove(os.path.join(self.folder, f))
        if self.name == "pyramid_update":
            shutil.copy(os.path.join(self.folder, "a.pyramid.gpkg"), self.pyramid)

    def trial(self, rng, i):
        self.reset()
        self.kill_once(self.cmd, rng.uniform(0.0, self.median_s))
        if not os.path.exists(self.pyramid):
            self.stats["absent"] += 1
        elif not whole(self.lacet, "scene.pyramid.gpkg", self.folder):
            self.stats["not_whole"] += 1
            self.fail("kill %d: scene.pyramid.gpkg does not open whole" % i)
        else:
            d = pyramid_digest(self.pyramid)
            self.stats["old_whole" if d == self.old else "new_whole"] += 1
        # Run again to the end: the tiles of an uninterrupted run.
        r = run(self.cmd, self.folder, check=False)
        if r.returncode != 0:
            self.stats["resumed_different"] += 1
            self.fail("kill %d: the run after it failed: %s" % (i, (r.stderr or r.stdout).strip().splitlines()[-1:]))
        elif pyramid_digest(self.pyramid) != self.expected:
            self.stats["resumed_different"] += 1
            self.fail("kill %d: the run after it gave other tiles than an uninterrupted run" % i)
        else:
            self.stats["resumed_equal"] += 1


class MpiPyramidWriter(PyramidWriter):
    """pyramid build --shards under mpirun -np 2: one rank killed at a random moment (the job then
    aborts); the pyramid is absent or whole, and a run again to the end (finished shards resumed,
    the rest made, merged) gives the uninterrupted tiles."""

    def __init__(self, name, lacet, folder):
        self.mpirun = shutil.which("mpirun")
        if not self.mpirun:
            sys.exit("kill_harness: pyramid_mpi needs mpirun (Open MPI) and a lacet built with LACET_MPI")
        Writer.__init__(self, name, lacet, folder)
        self.pyramid = os.path.join(folder, "scene.pyramid.gpkg")
        self.old = None
        run([lacet, "synth", "--curves", "1500", "--seed", "2", "--out", "b.gpkg"], folder)
        self.cmd = [self.mpirun, "--allow-run-as-root", "--oversubscribe", "-np", "2", lacet, "pyramid", "build", "scene.gpkg",
                    "--levels", "0-4", "--shard-level", "2", "--shards"]
        times = []
        for _ in range(3):
            self.reset()
            times.append(self.timed(self.cmd))
        self.expected = pyramid_digest(self.pyramid)
        self.median_s = statistics.median(times)

    def reset(self):
        shutil.copy(os.path.join(self.folder, "b.gpkg"), os.path.join(self.folder, "scene.gpkg"))
        for f in os.listdir(self.folder):
            if f.startswith("scene.pyramid.gpkg"):
                p = os.path.join(self.folder, f)
                shutil.rmtree(p) if os.path.isdir(p) else os.remove(p)

    def kill_once(self, cmd, delay):
        p = subprocess.Popen(cmd, cwd=self.folder, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
        try:
            p.wait(timeout=delay)
            self.stats["finished_before_kill"] += 1
        except subprocess.TimeoutExpired:
            # One of the ranks: the lacet processes of this job's session but mpirun.
            ranks = []
            for pid in os.listdir("/proc"):
                if not pid.isdigit():
                    continue
                try:
                    if os.getsid(int(pid)) != p.pid:
                        continue
                    with open("/proc/%s/cmdline" % pid, "rb") as f:
                        argv = f.read().split(b"\0")
                    if os.path.basename(argv[0].decode()) == os.path.basename(self.lacet):
                        ranks.append(int(pid))
                except (OSError, ValueError):
                    continue
            if ranks:
                os.kill(random.choice(ranks), signal.SIGKILL)
                self.stats["killed_before_done"] += 1
            else:  # not started or already ending: the job itself
                os.killpg(p.pid, signal.SIGKILL)
                self.stats["killed_before_done"] += 1
            try:
                p.wait(timeout=120)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait()
        self.stats["kills"] += 1


def make(name, lacet, folder):
    if name == "save":
        return SceneWriter(name, lacet, folder, [lacet, "synth", "--curves", "300", "--seed", "2", "--out", "scene.gpkg"])
    if name in ("import", "import_parts"):
        # A DEM under the test vectors (lon 1.4-1.65, lat 42.4-42.6, about 80 m cells), made here
        # with GDAL's gdal_create (gdal-bin, which scripts/install_deps.sh installs).
        run(["gdal_create", "-q", "-of", "GTiff", "-outsize", "300", "240", "-bands", "1", "-ot", "Float32", "-burn", "1200",
             "-a_srs", "EPSG:4326", "-a_ullr", "1.4", "42.6", "1.65", "42.4", "dem.tif"], folder)
        # import_parts: the vectors out of core (a spill file beside the scene, 4 x 4 parts).
        parts = ["--vector-part-level", "2"] if name == "import_parts" else []
        return SceneWriter(name, lacet, folder, [lacet, "import", "--dem", "dem.tif", "--vectors", VECTORS, "--dem-storage", "lod",
                                                 "--out", "scene.gpkg"] + parts)
    if name in ("pyramid_build", "pyramid_update"):
        return PyramidWriter(name, lacet, folder)
    if name == "pyramid_mpi":
        return MpiPyramidWriter(name, lacet, folder)
    sys.exit("kill_harness: unknown writer '%s'" % name)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--kills", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--landed", action="store_true", help="go on until KILLS trials were killed before their end")
    ap.add_argument("--writers", default="save,import,import_parts,pyramid_build,pyramid_update")
    ap.add_argument("--lacet", default=os.path.join(ROOT, "build", "lacet"))
    ap.add_argument("--work", default=None, help="scratch folder (default: a new one in /tmp, removed at the end)")
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    lacet = os.path.abspath(a.lacet)
    work = a.work or tempfile.mkdtemp(prefix="lacet_kill_")
    rng = random.Random(a.seed)
    results, ok = {}, True
    for name in a.writers.split(","):
        folder = os.path.join(work, name)
        os.makedirs(folder, exist_ok=True)
        t0 = time.monotonic()
        w = make(name, lacet, folder)
        i = 0
        while (w.stats["killed_before_done"] < a.kills and i < 4 * a.kills) if a.landed else i < a.kills:
            w.trial(rng, i)
            i += 1
            if not a.json and i % 100 == 0:
                print("%-15s %d trials (%d killed before the end), %d failures, %.0f s" %
                      (name, i, w.stats["killed_before_done"], len(w.failures), time.monotonic() - t0), file=sys.stderr)
        # The writer run to the end once more: it removes what the kills left.
        if isinstance(w, SceneWriter):
            run(w.make_new, folder)
        left = temporaries(folder)
        if left:
            w.fail("left behind after a complete run: %s" % ", ".join(left[:5]) + (" and %d more" % (len(left) - 5) if len(left) > 5 else ""))
        w.stats["temporaries_left"] = len(left)
        w.stats["run_median_s"] = round(w.median_s, 3)
        w.stats["wall_s"] = round(time.monotonic() - t0, 1)
        w.stats["failures"] = w.failures[:20]
        results[name] = w.stats
        ok = ok and not w.failures
        if not a.json:
            s = w.stats
            print("%-15s kills %5d (%d before the end): old %d, new %d, absent %d, not whole %d, mixture %d; resumed equal %d, "
                  "different %d; temporaries left %d; a run %.3f s; %.0f s" %
                  (name, s["kills"], s["killed_before_done"], s["old_whole"], s["new_whole"], s["absent"], s["not_whole"], s["mixture"],
                   s["resumed_equal"], s["resumed_different"], s["temporaries_left"], s["run_median_s"], s["wall_s"]))
            for f in w.failures[:20]:
                print("  " + f)
    if a.json:
        print(json.dumps({"seed": a.seed, "kills_per_writer": a.kills, "writers": results}, indent=2))
    if not a.work:
        shutil.rmtree(work, ignore_errors=True)
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
