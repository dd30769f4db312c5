#!/bin/bash
# Submits the photon reference (or the ray-traced camera reference, by rows) to Slurm as a job array of shards, or a bench sweep as a job array of
# cells (--bench), and a merge that runs when every task has succeeded (--dependency=afterok), and
# prints both job ids (docs/cluster.md).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)

usage() {
  cat <<'USAGE'
usage: tools/slurm/submit.sh --scene S --photons N --shards K --out MAP.exr [options]
       tools/slurm/submit.sh --scene S --size WxH --shards K --out IMAGE.exr [options]
       tools/slurm/submit.sh --bench accuracy|stability [--sweep "OPTIONS"] --out DIR [--reference-cache DIR] [options]

Submits K array tasks (tools/slurm/reference.sbatch), each `caustica reference --shard auto/K`
writing MAP.shards/shard_I.exr, and a merge job (merge.sbatch) after them that writes MAP.exr.
With --size instead of --photons: the camera reference (`caustica reference --size WxH`), each
task tracing one K-th of the image's rows, the merge writing IMAGE.exr. Prints the array's and the
merge's job ids. A scene's whole picture of several lights (`caustica reference --picture`) on a
cluster: each light's map with --light I (its --photons share as --picture prints it), then the
picture with --size and --caustics I=MAP.exr for each light's merged map.

With --bench: one array task per cell of `caustica bench BENCH OPTIONS` (as many as --list-cells
prints here), each `--cell auto` through tools/slurm/bench.sbatch writing DIR/cells/cell_I.csv, the
photon references shared in --reference-cache (default DIR/references); then `caustica bench merge`
writes DIR/results.csv and the rest (stability: DIR/stability.csv). OPTIONS are split at spaces.

options:
  --seed K            random seed (default 1)
  --map-size N        side of the caustic map (default 512)
  --light I           with --photons: the light whose photons are traced (default 0)
  --caustics I=MAP    with --size: light the picture with light I's map (repeatable; a path
                      without spaces)
  --partition P       sbatch --partition for both jobs
  --account A         sbatch --account for both jobs
  --time T            sbatch --time per shard (e.g. 00:30:00); the merge gets 10 minutes
  --cpus C            cores per shard (sbatch --cpus-per-task); a shard uses every core it is given
  --throttle N        at most N shards at once (--array=0-(K-1)%N)
  --resubmit I[,J..]  submit only these indices (shards or cells) again (those that failed: merge names them) and a
                      new merge after them (Slurm cancels the first merge when a shard fails:
                      --kill-on-invalid-dep)
  --caustica BIN      the caustica binary the nodes run (default: caustica on PATH)
  --dry-run           print the sbatch commands instead of running them
USAGE
}

seed=1 map_size=512 light=0 scene="" photons="" size="" shards="" out="" caustica=caustica throttle="" resubmit="" dry_run="" bench="" sweep="" cache=""
common=() shard_time=() caustics=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --scene) scene=$2; shift 2 ;;
    --photons) photons=$2; shift 2 ;;
    --size) size=$2; shift 2 ;;
    --shards) shards=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --bench) bench=$2; shift 2 ;;
    --sweep) sweep=$2; shift 2 ;;
    --reference-cache) cache=$2; shift 2 ;;
    --map-size) map_size=$2; shift 2 ;;
    --light) light=$2; shift 2 ;;
    --caustics) caustics+=("$2"); shift 2 ;;
    --partition) common+=(--partition "$2"); shift 2 ;;
    --account) common+=(--account "$2"); shift 2 ;;
    --time) shard_time+=(--time "$2"); shift 2 ;;
    --cpus) shard_time+=(--cpus-per-task "$2"); shift 2 ;;
    --throttle) throttle=$2; shift 2 ;;
    --resubmit) resubmit=$2; shift 2 ;;
    --caustica) caustica=$2; shift 2 ;;
    --dry-run) dry_run=1; shift ;;
    -h|--help) usage; exit 0 ;;
    *) echo "submit.sh: unknown option '$1'; see --help" >&2; exit 2 ;;
  esac
done
if [[ -n $bench ]]; then
  if [[ $bench != accuracy && $bench != stability ]]; then echo "submit.sh: --bench $bench: expected accuracy or stability" >&2; exit 2; fi
  if [[ -z $out ]]; then echo "submit.sh: --bench needs --out DIR; see --help" >&2; exit 2; fi
elif [[ -z $scene || -z $photons$size || -z $shards || -z $out ]]; then
  echo "submit.sh: --scene, --photons (or --size), --shards and --out are required; see --help" >&2
  exit 2
elif [[ -n $photons && -n $size ]]; then
  echo "submit.sh: --photons or --size, not both: the photon reference or the camera image" >&2
  exit 2
elif ! [[ $shards =~ ^[1-9][0-9]*$ ]]; then echo "submit.sh: --shards $shards: expected a whole number from 1" >&2; exit 2; fi
if [[ ${#caustics[@]} -gt 0 && -z $size ]]; then echo "submit.sh: --caustics goes with --size: the maps light the camera picture" >&2; exit 2; fi
if [[ $light != 0 && -z $photons ]]; then echo "submit.sh: --light goes with --photons: the light whose photons are traced" >&2; exit 2; fi
if [[ -n $throttle && ! $throttle =~ ^[1-9][0-9]*$ ]]; then echo "submit.sh: --throttle $throttle: expected a whole number from 1" >&2; exit 2; fi
if [[ -n $resubmit && ! $resubmit =~ ^[0-9]+(,[0-9]+)*$ ]]; then echo "submit.sh: --resubmit $resubmit: expected indices, e.g. 3 or 3,17" >&2; exit 2; fi

# The nodes may start elsewhere: every path absolute. A scene given by its bundled name stays a name.
out=$(realpath -m "$out")
[[ -e $scene ]] && scene=$(realpath "$scene")
[[ $caustica == */* ]] && caustica=$(realpath "$caustica")
submit() {
  if [[ -n $dry_run ]]; then
    echo "sbatch $*" >&2
    echo "DRY"
  else
    sbatch --parsable "$@" | cut -d';' -f1
  fi
}
if [[ -n $bench ]]; then
  # The cells are counted here, by the binary the nodes run: the sweep's options alone decide them.
  read -r -a sweep_words <<<"$sweep"
  cells=$("$caustica" bench "$bench" "${sweep_words[@]}" --list-cells | wc -l)
  if [[ $cells -eq 0 ]]; then echo "submit.sh: bench $bench $sweep --list-cells printed no cells" >&2; exit 1; fi
  cell_dir=$out/cells
  cache=$(realpath -m "${cache:-$out/references}")
  mkdir -p "$cell_dir" "$cache"
  array=${resubmit:-0-$((cells - 1))}${throttle:+%$throttle}
  # Through the environment, not --export's list: the sweep's options hold commas.
  export CAUSTICA=$caustica BENCH=$bench SWEEP=$sweep CELL_DIR=$cell_dir REFERENCE_CACHE=$cache
  # The jobs' output beside the cells, not in the folder sbatch was called from.
  cell_job=$(submit "${common[@]}" "${shard_time[@]}" --array="$array" --output="$cell_dir/caustica-cell-%A_%a.out" --export=ALL "$here/bench.sbatch")
  merge_job=$(submit "${common[@]}" --time=00:10:00 --dependency="afterok:$cell_job" --kill-on-invalid-dep=yes --export=ALL \
    --job-name=caustica-bench-merge --output="$cell_dir/caustica-bench-merge-%j.out" --wrap="exec $(printf '%q ' "$caustica" bench merge "$cell_dir" --out "$out")")
  echo "cells:  job $cell_job (array $array of $cells cells, $cell_dir/cell_I.csv)"
  echo "merge:  job $merge_job (after every cell succeeded; writes $out)"
  echo "a failed cell: tools/slurm/submit.sh ... --resubmit I (the same options, the indices that failed)"
  exit 0
fi

shard_dir=${out%.exr}.shards
mkdir -p "$shard_dir"
# The maps through the environment (their paths absolute, as the nodes see them), each I=MAP.
maps=()
for map in "${caustics[@]+"${caustics[@]}"}"; do
  if [[ $map =~ ^[0-9]+= ]]; then maps+=("${map%%=*}=$(realpath -m "${map#*=}")"); else maps+=("$(realpath -m "$map")"); fi
done
export REFERENCE_CAUSTICS="${maps[*]+"${maps[*]}"}"
array=${resubmit:-0-$((shards - 1))}${throttle:+%$throttle}
# Through the environment and --export=ALL, not --export=ALL,NAME=VALUE: with a list Slurm also
# loads the user's login environment on the node (slurmd runs `su - USER` per job: a login shell
# and whatever the user's profile starts, 1 s of the node's time a job on the test machine).
export CAUSTICA=$caustica SCENE=$scene PHOTONS=$photons SIZE=$size SHARDS=$shards SEED=$seed MAP_SIZE=$map_size LIGHT=$light \
  SHARD_DIR=$shard_dir OUT=$out
# The jobs' output beside the shards, not in the folder sbatch was called from.
shard_job=$(submit "${common[@]}" "${shard_time[@]}" --array="$array" --output="$shard_dir/caustica-shard-%A_%a.out" --export=ALL "$here/reference.sbatch")
merge_job=$(submit "${common[@]}" --time=00:10:00 --dependency="afterok:$shard_job" --kill-on-invalid-dep=yes --output="$shard_dir/caustica-merge-%j.out" --export=ALL "$here/merge.sbatch")
echo "shards: job $shard_job (array $array, $shard_dir/shard_I.exr)"
echo "merge:  job $merge_job (after every shard succeeded; writes $out)"
echo "a failed shard: tools/slurm/submit.sh ... --resubmit I (the same options, the indices that failed)"
