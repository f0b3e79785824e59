#!/usr/bin/env bash
# ./tests/bench.sh sac-update: the SAC update of learner/sac.cc (bench_sac_update: 1 and 2
# learner threads, oneDNN vs Eigen GEMM, GEMM floor, sgemm rates) and, in the same invocation, its PyTorch
# peer (torch_peer.py: the same networks, SAC settings and batch, which the C++ bench writes
# out) pinned to the same thread count: torch.set_num_threads and the OpenMP / OpenBLAS
# thread counts, with passive OpenMP waiting (spinning OpenMP threads lose their time slices
# on a machine shared with other work: PyTorch with 2 threads took 8x longer than with 1 on
# the loaded development machine). Installs python3-torch, python3-numpy and libopenblas0-pthread when missing
# (Debian's torch multiplies through the system BLAS, OpenBLAS with this package).
#   tests/bench/sac-update/run.sh BUILD_DIR
# Prints the C++ table, the PyTorch table and, as its last line, one JSON object: the C++
# figures, torch_ms_batch2048/256 (one thread), speedup_vs_torch_2048/256 (PyTorch's update
# time over the agent's update on the same batch, one thread each), the same including our
# batch sampling and relabeling (..._with_sampling), the sgemm peak (the best of Eigen, oneDNN,
# torch.mm and numpy at 2048^3, one thread), the update's GEMM rate as fraction_of_peak_2048,
# and PyTorch with 2 threads beside our 2-thread update. Beside the wall times, CPU times per
# update (speedup_vs_torch_cpu_*) and the cores the process obtained (cores_*): on a shared
# machine these say what the wall times cannot.
set -euo pipefail
root="$(cd "$(dirname "$0")/../../.." && pwd)"
build="${1:-$root/build}"
here="$root/tests/bench/sac-update"
py=/usr/bin/python3  # Debian's interpreter: python3-torch lives there

missing=()
for p in python3-torch python3-numpy libopenblas0-pthread; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "sac-update: installing ${missing[*]} (the PyTorch peer)" >&2
  sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq >&2
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$build/tests/bench/sac-update/bench_sac_update" --dump "$work" >"$work/cpp.out"
grep -v '^{' "$work/cpp.out"
echo
for t in 1 2; do
  OMP_NUM_THREADS=$t OPENBLAS_NUM_THREADS=$t MKL_NUM_THREADS=$t OMP_WAIT_POLICY=PASSIVE "$py" "$here/torch_peer.py" "$work" --threads "$t" \
    >"$work/torch$t.out"
  grep -v '^{' "$work/torch$t.out"
  echo
done
"$py" - "$work" <<'PY'
import json, sys
work = sys.argv[1]
def last_json(name):
    with open(f"{work}/{name}") as f:
        return json.loads([l for l in f if l.startswith("{")][-1])
cpp, t1, t2 = last_json("cpp.out"), last_json("torch1.out"), last_json("torch2.out")
out = dict(cpp)
for b in (2048, 256):
    out[f"torch_ms_batch{b}"] = t1[f"torch_ms_batch{b}"]
    out[f"speedup_vs_torch_{b}"] = round(t1[f"torch_ms_batch{b}"] / cpp[f"agent_ms_batch{b}"], 3)
    out[f"speedup_vs_torch_{b}_with_sampling"] = round(t1[f"torch_ms_batch{b}"] / cpp[f"ms_batch{b}"], 3)
    # CPU time per update, one thread each: the work, whatever share of the machine we got
    out[f"torch_cpu_ms_batch{b}"] = t1[f"torch_cpu_ms_batch{b}"]
    out[f"speedup_vs_torch_cpu_{b}"] = round(t1[f"torch_cpu_ms_batch{b}"] / cpp[f"agent_cpu_ms_batch{b}"], 3)
    out[f"torch_ms_batch{b}_2threads"] = t2[f"torch_ms_batch{b}"]
    out[f"speedup_vs_torch_{b}_2threads"] = round(t2[f"torch_ms_batch{b}"] / cpp[f"agent_ms_batch{b}_2threads"], 3)
# the peak and the update's rate by CPU time (one thread each: CPU time is the work, whatever
# share of the machine the process got); the wall-time figures beside them
peaks = {"eigen": cpp["eigen_sgemm_gflops_cpu"], "onednn": cpp["onednn_sgemm_gflops_cpu"], "torch.mm": t1["torch_sgemm_gflops_cpu"],
         "numpy": t1["numpy_sgemm_gflops_cpu"]}
peaks_wall = {"eigen": cpp["eigen_sgemm_gflops"], "onednn": cpp["onednn_sgemm_gflops"], "torch.mm": t1["torch_sgemm_gflops"], "numpy": t1["numpy_sgemm_gflops"]}
source = max(peaks, key=peaks.get)
out["sgemm_peak_gflops"] = peaks[source]
out["sgemm_peak_source"] = source
out["sgemm_peak_gflops_wall"] = max(peaks_wall.values())
out["update_gflops_2048"] = round(cpp["gflop_update_2048"] / (cpp["agent_cpu_ms_batch2048"] * 1e-3), 2)
out["fraction_of_peak_2048"] = round(out["update_gflops_2048"] / peaks[source], 3)
out["update_gflops_2048_wall"] = round(cpp["gflop_update_2048"] / (cpp["agent_ms_batch2048"] * 1e-3), 2)
out["fraction_of_peak_2048_wall"] = round(out["update_gflops_2048_wall"] / out["sgemm_peak_gflops_wall"], 3)
out["torch_version"] = t1["torch_version"]
out["torch_threads"] = t1["torch_threads"]
out["openblas_threads"] = t1["openblas_threads"]
print(f"one thread: SAC update vs PyTorch {out['speedup_vs_torch_2048']:.2f}x at batch 2048, "
      f"{out['speedup_vs_torch_256']:.2f}x at 256 (with our sampling and relabeling: "
      f"{out['speedup_vs_torch_2048_with_sampling']:.2f}x, {out['speedup_vs_torch_256_with_sampling']:.2f}x)")
print(f"one thread, CPU time per update: {out['speedup_vs_torch_cpu_2048']:.2f}x at 2048, "
      f"{out['speedup_vs_torch_cpu_256']:.2f}x at 256 (the process got {cpp['cores_1thread_2048']:.2f} of a core)")
print(f"two threads each: {out['speedup_vs_torch_2048_2threads']:.2f}x at 2048, {out['speedup_vs_torch_256_2threads']:.2f}x at 256")
print(f"sgemm peak (one thread, 2048^3, by CPU time): {peaks[source]:.1f} GFLOP/s ({source}; "
      + ", ".join(f"{k} {v:.1f}" for k, v in peaks.items()) + ")")
print(f"update at 2048 (1 thread, by CPU time): {out['update_gflops_2048']:.1f} GFLOP/s of GEMM work = "
      f"{out['fraction_of_peak_2048']:.2f} of the peak (by wall time: {out['fraction_of_peak_2048_wall']:.2f})")
print(json.dumps(out, separators=(",", ":")))
PY
