#!/usr/bin/env bash
# Submits the three steps of a sharded run, chained with --dependency=afterok:
#   experiments/slurm/submit.sh experiments/paper.toml 3 [extra sbatch options, e.g. --partition=short]
# Run from the repository root after `cargo build --release`. Prints the three job ids.
set -euo pipefail
spec=${1:?usage: submit.sh SPEC.toml N [sbatch options]}
n=${2:?usage: submit.sh SPEC.toml N [sbatch options]}
shift 2
here=$(dirname "$0")
ref=$(sbatch --parsable "$@" "$here/reference.sbatch" "$spec")
shards=$(sbatch --parsable "$@" --array=0-$((n - 1)) --dependency=afterok:"$ref" "$here/shard.sbatch" "$spec")
merge=$(sbatch --parsable "$@" --dependency=afterok:"$shards" "$here/merge.sbatch" "$spec" "$n")
echo "reference $ref, shards $shards (array 0-$((n - 1))), merge $merge"
