# The Nsight Compute metrics of scripts/profile.sh and scripts/profile-occupancy.sh (sourced):
# time, DRAM traffic and its share of peak, achieved occupancy, registers, SM throughput, and
# what bounds a kernel that is not DRAM-bound: issue slots busy and L1 throughput.
metrics=gpu__time_duration.sum,dram__bytes_read.sum,dram__bytes_write.sum
metrics+=,gpu__dram_throughput.avg.pct_of_peak_sustained_elapsed
metrics+=,sm__warps_active.avg.pct_of_peak_sustained_active,launch__registers_per_thread
metrics+=,sm__throughput.avg.pct_of_peak_sustained_elapsed
metrics+=,smsp__issue_active.avg.pct_of_peak_sustained_active,l1tex__throughput.avg.pct_of_peak_sustained_active
