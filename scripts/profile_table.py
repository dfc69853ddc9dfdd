#!/usr/bin/env python3
"""Per-kernel table from an ncu --csv --print-units base report of `perifrac bench`.

Kernels are named by the launcher that wraps them (the lambda's enclosing function appears in
the kernel's name: launch_springforces_variant -> springforces); CUB's sort and scan kernels are
named after the CUB algorithm. Usage: profile_table.py REPORT.csv BONDS
"""
import csv
import re
import sys
from collections import OrderedDict


def kernel_label(name):
    # A kernel run over a particle range is wrapped by launch_over_range: its variant names it.
    m = re.search(r"launch_([a-z_]+?)_variant<", name) or re.search(r"launch_([a-z_]+?)<", name)
    if m:
        return m.group(1)
    for cub in ("RadixSort", "Scan", "Reduce", "Histogram"):
        if cub in name:
            return "cub " + cub.lower()
    return name.split("(")[0][-40:]


def number(text):
    return float(text.replace(",", "")) if text not in ("", "n/a") else 0.0


def read_launches(path, label=kernel_label):
    """ID -> (label(kernel name), {metric: value}) for each launch of an ncu --csv report; the
    profiled program's own output before ncu's header is skipped."""
    launches = OrderedDict()
    with open(path, newline="") as f:
        lines = [line for line in f if line.startswith('"')]
    for row in csv.DictReader(lines):
        entry = launches.setdefault(row["ID"], (label(row["Kernel Name"]), {}))
        entry[1][row["Metric Name"]] = number(row["Metric Value"])
    return launches


def main():
    path, bonds = sys.argv[1], float(sys.argv[2])
    launches = read_launches(path)
    table = OrderedDict()
    for label, m in launches.values():
        t = table.setdefault(label, {"n": 0, "ns": 0.0, "bytes": 0.0, "dram_pct": 0.0, "occ": 0.0,
                                     "sm_pct": 0.0, "issue": 0.0, "l1": 0.0, "regs": 0})
        t["n"] += 1
        t["ns"] += m.get("gpu__time_duration.sum", 0)
        t["bytes"] += m.get("dram__bytes_read.sum", 0) + m.get("dram__bytes_write.sum", 0)
        t["dram_pct"] += m.get("gpu__dram_throughput.avg.pct_of_peak_sustained_elapsed", 0)
        t["sm_pct"] += m.get("sm__throughput.avg.pct_of_peak_sustained_elapsed", 0)
        t["occ"] += m.get("sm__warps_active.avg.pct_of_peak_sustained_active", 0)
        t["issue"] += m.get("smsp__issue_active.avg.pct_of_peak_sustained_active", 0)
        t["l1"] += m.get("l1tex__throughput.avg.pct_of_peak_sustained_active", 0)
        t["regs"] = int(m.get("launch__registers_per_thread", 0))
    print("| kernel | launches | us/launch | DRAM GB/s | DRAM % of peak | SM % | issue % | L1 % | B per bond | regs | "
          "achieved occupancy % |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for label, t in table.items():
        n = t["n"]
        us = t["ns"] / n / 1e3
        gbs = t["bytes"] / t["ns"] if t["ns"] > 0 else 0
        per_bond = t["bytes"] / n / bonds
        print(f"| {label} | {n} | {us:.1f} | {gbs:.0f} | {t['dram_pct'] / n:.0f} | {t['sm_pct'] / n:.0f} | "
              f"{t['issue'] / n:.0f} | {t['l1'] / n:.0f} | {per_bond:.2f} | {t['regs']} | {t['occ'] / n:.0f} |")


if __name__ == "__main__":
    main()
