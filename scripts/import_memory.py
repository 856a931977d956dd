#!/usr/bin/env python3
"""Peak memory and time of `lacet import` of synthetic OSM extracts, in memory and out of core
(--vector-budget), printed as JSON (issue 23: memory bounded by a knob, not by the extract).

For each --blocks size, scripts/synthetic_osm.py writes the extract into --work; each import then
runs as a child process whose peak RSS comes from wait4 (ru_maxrss), with its wall time and the
import's own report (parts, border nodes, bytes spilled). The peak includes what every run of the
binary maps (its shared libraries: about 130 MiB here) and GDAL's OSM reader.
With --format pbf each extract is also written as PBF by osmium-tool (`osmium cat`) and that is imported.

  scripts/import_memory.py --lacet build/lacet --blocks 150 300 --budgets 0 16 64 256 --work /tmp/im
  scripts/import_memory.py --blocks 600 --budgets 16 64 --format pbf --work /tmp/im
"""
import argparse
import json
import os
import subprocess
import sys
import time


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('--lacet', default=os.path.join(here, '..', 'build', 'lacet'))
    p.add_argument('--blocks', type=int, nargs='+', default=[150])
    p.add_argument('--budgets', type=float, nargs='+', default=[0, 64], help='MiB; 0 imports in memory')
    p.add_argument('--seed', type=int, default=1)
    p.add_argument('--work', required=True, help='a folder for the extracts and scenes')
    p.add_argument('--format', choices=['osm', 'pbf'], default='osm', help='the extract imported: OSM XML or PBF')
    a = p.parse_args()
    os.makedirs(a.work, exist_ok=True)
    results = []
    for blocks in a.blocks:
        osm = os.path.join(a.work, f'synthetic_{blocks}_{a.seed}.osm')
        if not os.path.exists(osm):
            subprocess.run([sys.executable, os.path.join(here, 'synthetic_osm.py'), '--blocks', str(blocks), '--seed', str(a.seed),
                            '--out', osm], check=True)
        if a.format == 'pbf':
            pbf = osm + '.pbf'
            if not os.path.exists(pbf):
                subprocess.run(['osmium', 'cat', osm, '-o', pbf], check=True)
            osm = pbf
        for budget in a.budgets:
            out = os.path.join(a.work, f'scene_{blocks}_{budget:g}.gpkg')
            cmd = [a.lacet, 'import', '--vectors', osm, '--out', out, '--json']
            if budget > 0:
                cmd += ['--vector-budget', f'{budget:g}']
            t0 = time.monotonic()
            child = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
            stdout = child.stdout.read()
            stderr = child.stderr.read()
            _, status, usage = os.wait4(child.pid, 0)
            wall = time.monotonic() - t0
            child.returncode = os.waitstatus_to_exitcode(status)
            if child.returncode != 0:
                sys.exit(f'import_memory.py: {" ".join(cmd)} failed ({child.returncode}):\n{stderr.decode(errors="replace")}')
            report = json.loads(stdout)
            results.append({
                'blocks': blocks,
                'format': a.format,
                'extract_bytes': os.path.getsize(osm),
                'features_read': report['features_read'],
                'vector_budget_mib': budget,
                'peak_rss_mib': round(usage.ru_maxrss / 1024.0, 1),
                'wall_s': round(wall, 2),
                'scene_bytes': os.path.getsize(out),
                'out_of_core': report.get('vectors_out_of_core'),
                'max_fit_error_m': report['fit']['max_error_m'],
            })
            os.remove(out)
            print(json.dumps(results[-1]), file=sys.stderr)
    print(json.dumps({'command': ' '.join(sys.argv), 'runs': results}, indent=2))


if __name__ == '__main__':
    main()
