#!/usr/bin/env python3
"""A million random edits (issue 26): `lacet check incremental --sample` over consecutive seeds,
each seed a synthetic scene of CURVES curves edited CHUNK times, until EDITS edits were applied;
after each edit SAMPLE random quads of the updated quadtree are compared with the same quads
rebuilt from scratch, and every quad every FULL_EVERY edits (the edits are those of the full check:
a mismatch a sample finds late is found at its edit by `--sample 0`). Edits of every kind, the
graph step's bridges and roundabouts and the bridge and tunnel flags included; each edit undone
with probability UNDO after its comparison and compared again, half of those redone and compared.

  scripts/million_edits.py SEED [--edits 1000000] [--chunk 2000] [--curves 300] [--depth 12]
                           [--sample 16] [--full-every 1000] [--undo 0.3] [--jobs 1] [--lacet build/lacet] [--json]

A nightly run: scripts/million_edits.py $(date +%Y%m%d). Prints one line per chunk as it ends
(seed, edits, mismatches, seconds), then the totals (or JSON); exits 1 on any mismatch, an
invalid scene or a chunk that failed, naming the seed that reproduces it:
  lacet check incremental --seed S --curves C --edits CHUNK --depth D --undo UNDO --sample 0
"""
import argparse
import concurrent.futures
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run_chunk(args, seed):
    cmd = [args.lacet, "check", "incremental", "--seed", str(seed), "--curves", str(args.curves),
           "--edits", str(args.chunk), "--depth", str(args.depth), "--sample", str(args.sample),
           "--full-every", str(args.full_every), "--undo", str(args.undo), "--json"]
    t0 = time.monotonic()
    p = subprocess.run(cmd, capture_output=True, text=True)
    seconds = time.monotonic() - t0
    try:
        report = json.loads(p.stdout)
    except json.JSONDecodeError:
        return {"seed": seed, "failed": f"exit {p.returncode}, no report: {p.stderr.strip()[-400:]}", "seconds": seconds}
    report["seed"] = seed
    report["seconds"] = seconds
    report["exit"] = p.returncode
    return report


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("seed", type=int, help="first seed (a nightly run: the date)")
    ap.add_argument("--edits", type=int, default=1000000, help="edits applied in all (at least)")
    # Short chunks keep each scene near its size: edits add elements, and a seed edited 10,000
    # times cost 13-14 ms an edit instead of about 5 (2026-12-07, this 2-core machine).
    ap.add_argument("--chunk", type=int, default=2000, help="edits tried per seed")
    ap.add_argument("--curves", type=int, default=300, help="curves of each seed's synthetic scene")
    ap.add_argument("--depth", type=int, default=12, help="deepest quadtree level around the viewers")
    ap.add_argument("--sample", type=int, default=16, help="quads compared after each edit")
    ap.add_argument("--full-every", type=int, default=1000, help="every quad compared every this many edits")
    ap.add_argument("--undo", type=float, default=0.3, help="probability that an edit is undone (and half of those redone)")
    ap.add_argument("--jobs", type=int, default=1, help="chunks run at once (one core each)")
    ap.add_argument("--lacet", default=os.path.join(ROOT, "build", "lacet"))
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    if args.edits < 1 or args.chunk < 1 or args.jobs < 1 or args.sample < 1:
        ap.error("--edits, --chunk, --jobs and --sample must be positive")
    if not os.access(args.lacet, os.X_OK):
        ap.error(f"{args.lacet}: no lacet executable (build it first: scripts/build.sh build)")

    t0 = time.monotonic()
    chunks, applied, next_seed = [], 0, args.seed
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        running = set()
        while applied < args.edits or running:
            # Enough chunks in flight to reach the goal if each applies all it tries.
            while len(running) < args.jobs and applied + args.chunk * len(running) < args.edits:
                running.add(pool.submit(run_chunk, args, next_seed))
                next_seed += 1
            if not running:
                break
            done, running = concurrent.futures.wait(running, return_when=concurrent.futures.FIRST_COMPLETED)
            for f in done:
                r = f.result()
                chunks.append(r)
                applied += r.get("edits", 0)
                if not args.json:
                    state = r.get("failed") or (f"{r['edits']} edits ({r.get('undos', 0)} undone, {r.get('redos', 0)} redone), "
                                                f"{r['mismatches']} mismatches, scene valid: {r['scene_valid']}")
                    print(f"seed {r['seed']}: {state}, {r['seconds']:.0f} s", flush=True)
    bad = [c for c in chunks if c.get("failed") or c.get("mismatches", 0) or not c.get("scene_valid", False) or c.get("exit", 1)]
    kinds = {}
    for c in chunks:
        for k, n in c.get("edits_by_kind", {}).items():
            kinds[k] = kinds.get(k, 0) + n
    summary = {
        "first_seed": args.seed,
        "seeds": len(chunks),
        "curves": args.curves,
        "depth": args.depth,
        "sample": args.sample,
        "full_every": args.full_every,
        "undo": args.undo,
        "edits": sum(c.get("edits", 0) for c in chunks),
        "undos": sum(c.get("undos", 0) for c in chunks),
        "redos": sum(c.get("redos", 0) for c in chunks),
        "edits_by_kind": kinds,
        "quads_compared": sum(c.get("quads_compared", 0) for c in chunks),
        "full_comparisons": sum(c.get("full_comparisons", 0) for c in chunks),
        "mismatches": sum(c.get("mismatches", 0) for c in chunks),
        "edits_adding_bridges": sum(c.get("graph_step", {}).get("edits_adding_bridges", 0) for c in chunks),
        "edits_adding_roundabout_arcs": sum(c.get("graph_step", {}).get("edits_adding_roundabout_arcs", 0) for c in chunks),
        "failed_seeds": [c["seed"] for c in bad],
        "cpu_s": sum(c["seconds"] for c in chunks),
        "wall_s": time.monotonic() - t0,
    }
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        print(f"{summary['edits']} edits ({summary['undos']} undone, {summary['redos']} redone) over {summary['seeds']} seeds "
              f"from {args.seed} ({args.curves} curves each): "
              f"{summary['quads_compared']} quad comparisons ({summary['full_comparisons']} of every quad), "
              f"{summary['mismatches']} mismatches; {summary['cpu_s']:.0f} s of chunks, {summary['wall_s']:.0f} s wall")
        for c in bad:
            print(f"FAILED seed {c['seed']}: {c.get('failed') or c.get('mismatch_details', [])[:3]}\n  reproduce: {args.lacet} check "
                  f"incremental --seed {c['seed']} --curves {args.curves} --edits {args.chunk} --depth {args.depth} "
                  f"--undo {args.undo} --sample 0",
                  file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
