#!/usr/bin/env bash
# Nsight Compute's view of chapter 08's traversal kernels on one scene: time, L1/texture and L2
# hit rates, load requests per pipe, DRAM bytes, instructions, occupancy; one line per memory
# path and ray type (the mean over the profiled launches).
#   tools/profile-paths.sh CH08_EXE SCENE.obj[.gz] OUT.csv
# Clocks are left as the GPU runs them (--clock-control none), as the benchmark runs.
set -euo pipefail
exe="$1"; scene="$2"; out="$3"
metrics=gpu__time_duration.sum,l1tex__t_sector_hit_rate.pct,lts__t_sector_hit_rate.pct
metrics+=,l1tex__t_requests_pipe_lsu_mem_global_op_ld.sum,l1tex__t_requests_pipe_tex_mem_texture.sum
metrics+=,dram__bytes_read.sum,smsp__inst_executed.sum,sm__warps_active.avg.pct_of_peak_sustained_active
ncu --clock-control none --kernel-name regex:'path_trace_kernel|camera_trace' \
  --metrics "$metrics" --csv --page raw \
  "$exe" --backend gpu --headless --benchmark "$scene" --frames 1 >"$out"
python3 "$(dirname "$0")/profile-summary.py" "$out"
