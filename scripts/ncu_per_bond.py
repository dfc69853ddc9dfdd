#!/usr/bin/env python3
"""Per-kernel table of what bounds a bond loop, from scripts/ncu-per-bond.sh's ncu --csv report.

The kernels that visit bonds (springforces, init) get a row per launch: time, warp instructions
executed and thread instructions per bond (32 x warp instructions / bonds, idle lanes included),
issue slots busy, active threads per warp, and the warp cycles between two issued instructions
split into their largest stall reasons. Usage: ncu_per_bond.py REPORT.csv BONDS
"""
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from profile_table import read_launches  # noqa: E402 (the report reader shared with profile.sh's table)

STALL = re.compile(r"smsp__average_warps_issue_stalled_(\w+)_per_issue_active\.ratio")


def kernel_label(name):
    m = re.search(r"launch_([a-z_]+?)_variant<([^>]*)>", name)
    if not m:
        return None
    args = ", ".join(a.strip() for a in m.group(2).split(",") if "Exec" not in a)
    return f"{m.group(1)}<{args}>"


def main():
    path, bonds = sys.argv[1], float(sys.argv[2])
    launches = [(label, m) for label, m in read_launches(path, kernel_label).values()
                if label and label.startswith(("springforces", "init"))]
    print("| kernel | ms | warp instructions | per bond | issue busy | threads / warp | cycles / issue | "
          "largest stalls (cycles / issue) | occupancy | registers | DRAM % | L1 hit | L2 hit |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: | ---: |")
    for label, m in launches:
        # "selected" is a warp issuing, not a stall.
        stalls = sorted(((v, STALL.match(k).group(1)) for k, v in m.items() if STALL.match(k)), reverse=True)
        top = ", ".join([f"{name.replace('_', ' ')} {v:.1f}" for v, name in stalls if name != "selected"][:3])
        inst = m.get("smsp__inst_executed.sum", 0.0)
        print(f"| {label} | {m.get('gpu__time_duration.sum', 0) / 1e6:.3f} | {inst / 1e6:.1f}M | "
              f"{32 * inst / bonds:.1f} | {m.get('smsp__issue_active.avg.pct_of_peak_sustained_active', 0):.1f}% | "
              f"{m.get('smsp__thread_inst_executed_per_inst_executed.ratio', 0):.1f} | "
              f"{m.get('smsp__average_warp_latency_per_inst_issued.ratio', 0):.2f} | {top} | "
              f"{m.get('sm__warps_active.avg.pct_of_peak_sustained_active', 0):.1f}% | "
              f"{m.get('launch__registers_per_thread', 0):.0f} | "
              f"{m.get('gpu__dram_throughput.avg.pct_of_peak_sustained_elapsed', 0):.1f}% | "
              f"{m.get('l1tex__t_sector_hit_rate.pct', 0):.1f}% | {m.get('lts__t_sector_hit_rate.pct', 0):.1f}% |")


if __name__ == "__main__":
    main()
