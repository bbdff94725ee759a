#!/usr/bin/env python3
"""Markdown tables from gistream bench results.json files.

  summarize.py OUT_DIR   (every OUT_DIR/*/results.json, one table row per step)
"""
import json
import pathlib
import sys


def fmt(v, digits=1):
    return "-" if v is None else f"{v:.{digits}f}"


def main():
    out = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "out/bench-scaling")
    print("| run | sessions | fps/session (min) | interval p50 / p95 / max ms | "
          "latency p50 / p95 / max ms | settle p50 / max ms | Jain | RSS MB | CPU % |")
    print("|---|---|---|---|---|---|---|---|---|")
    for results in sorted(out.glob("*/results.json")):
        doc = json.loads(results.read_text())
        for step in doc["steps"]:
            lat, iv = step["latency_ms"], step["interval_ms"]
            rss = max((s["max_rss_bytes"] for s in step["servers"]), default=0) / 2**20
            cpu = sum(s["cpu_percent"] for s in step["servers"])
            extra = ""
            if "interferer" in step:
                extra = f" (interferer: {step['interferer']['renders']} renders)"
            print(f"| {results.parent.name}{extra} | {step['sessions']} | "
                  f"{fmt(step['fps_mean'])} ({fmt(step['fps_min'])}) | "
                  f"{fmt(iv['p50'])} / {fmt(iv['p95'])} / {fmt(iv['max'], 0)} | "
                  f"{fmt(lat['p50'])} / {fmt(lat['p95'])} / {fmt(lat['max'], 0)} | "
                  f"{fmt(step['settle_ms']['p50'], 0)} / {fmt(step['settle_ms']['max'], 0)} | "
                  f"{step['jain_fairness']:.3f} | {rss:.0f} | {cpu:.0f} |")


if __name__ == "__main__":
    main()
