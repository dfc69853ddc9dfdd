// A report as `ncu --csv --print-units base` writes it, for the tests of the scripts that read
// one (scripts/profile_table.py, scripts/ncu_per_bond.py): the profiled program's own lines,
// then ncu's header and one row per metric of a kernel launch.
#pragma once

#include <fstream>
#include <string>

namespace pd::testing {

// Kernel names as ncu prints them: a bond pass wrapped by launch_over_range, and a plain one.
inline const std::string kNcuSpringforces =
    "void parallel_for_bounded_kernel<8, void launch_over_range<1, 8, CudaExec, void "
    "launch_springforces_variant<0, 0, 0, 0, 0, 1, 0, 1, CudaExec>(T9 &)>(long, T2)";
inline const std::string kNcuPositionUpdate =
    "void parallel_for_kernel<void launch_position_update_variant<0, 1, CudaExec>(T3 &)>(long, T1)";

class NcuReport {
 public:
  explicit NcuReport(const std::string& path) : out_(path) {
    out_ << "==PROF== Connected to process 1136\nsize       1000 particles, 64000 bonds\n";
    out_ << "\"ID\",\"Process ID\",\"Process Name\",\"Host Name\",\"thread Domain\",\"Id:Domain\",";
    out_ << "\"Kernel Name\",\"Context\",\"Stream\",\"Block Size\",\"Grid Size\",\"Device\",\"CC\",";
    out_ << "\"Section Name\",\"Metric Name\",\"Metric Unit\",\"Metric Value\"\n";
  }
  // One metric of launch `id`, its value as ncu prints it (thousands separated by commas).
  void metric(int id, const std::string& kernel, const std::string& name, const std::string& value) {
    out_ << '"' << id << "\",\"1136\",\"perifrac\",\"127.0.0.1\",\"1136 \",\"\",\"" << kernel
         << "\",\"1\",\"7\",\"(256, 1, 1)\",\"(3907, 1, 1)\",\"0\",\"9.0\",\"Command line profiler "
            "metrics\",\""
         << name << "\",\"\",\"" << value << "\"\n";
    out_.flush();
  }

 private:
  std::ofstream out_;
};

}  // namespace pd::testing
