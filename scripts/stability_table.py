#!/usr/bin/python3
"""Turns the STABILITY lines printed by the stability suite into a Markdown table (one row per case, solver and
precision). Usage: build/release/tests/engine/engine_tests --gtest_filter='Stability*' | scripts/stability_table.py"""
import sys


def main():
    rows = []
    for line in sys.stdin:
        if not line.startswith("STABILITY "):
            continue
        fields = dict(kv.split("=", 1) for kv in line.split()[1:])
        rows.append(fields)
    if not rows:
        sys.exit("stability_table.py: no STABILITY lines on standard input")
    print("| case | solver | real | steps | max stretch | max KE (J) | energy gain (J) | end state |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        end = r.get("end", "").replace(",", ", ")
        print(f"| {r.get('case')} | {r.get('solver')} | {r.get('real')} | {r.get('steps')} | {r.get('max_stretch', '–')} "
              f"| {r.get('max_ke', '–')} | {r.get('energy_gain', '–')} | {end} |")


if __name__ == "__main__":
    main()
