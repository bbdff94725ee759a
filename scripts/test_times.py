#!/usr/bin/env python3
"""Prints where a ctest run's time went: the slowest ctest entries (from
ctest's --output-junit file) and the slowest GoogleTest cases inside them
(from the per-suite XML that gistream_add_test_suites writes).

Usage: test_times.py BUILD_DIR [COUNT]   (`make test` calls it; COUNT 20)
"""
import glob
import os
import sys
import xml.etree.ElementTree as ET


def ctest_entries(path):
    root = ET.parse(path).getroot()
    for case in root.iter("testcase"):
        status = case.get("status", "")
        if case.find("failure") is not None:
            status = "failed"
        elif case.find("skipped") is not None:
            status = "skipped"
        yield case.get("name", "?"), float(case.get("time", "0") or 0), status


def gtest_cases(results_dir):
    for path in glob.glob(os.path.join(results_dir, "*.xml")):
        if os.path.basename(path) == "ctest.xml":
            continue
        try:
            root = ET.parse(path).getroot()
        except ET.ParseError:
            continue  # a suite killed mid-write (timeout): ctest names it
        for case in root.iter("testcase"):
            if case.get("result", "completed") != "completed":
                continue
            yield f"{case.get('classname', '?')}.{case.get('name', '?')}", float(case.get("time", "0"))


def table(title, rows, count):
    rows = sorted(rows, key=lambda r: -r[1])
    total = sum(r[1] for r in rows)
    print(f"\n{title}: {len(rows)} in all, {total:.1f} s summed")
    for name, seconds, *rest in rows[:count]:
        share = 100.0 * seconds / total if total > 0 else 0.0
        note = f"  ({rest[0]})" if rest and rest[0] not in ("", "run") else ""
        print(f"  {seconds:8.2f} s  {share:5.1f} %  {name}{note}")


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    build = sys.argv[1]
    count = int(sys.argv[2]) if len(sys.argv) > 2 else 20
    results = os.path.join(build, "test-results")
    junit = os.path.join(results, "ctest.xml")
    if os.path.exists(junit):
        table(f"The {count} slowest ctest entries", list(ctest_entries(junit)), count)
    cases = list(gtest_cases(results))
    if cases:
        table(f"The {count} slowest GoogleTest cases", cases, count)
    return 0


if __name__ == "__main__":
    sys.exit(main())
