# With --wait, returns when the merge job has ended, with its exit code.
wait_flag=()
if [ "${1:-}" = "--wait" ]; then wait_flag=(--wait); fi
mkdir -p "$OUT/logs"
array=$(sbatch --parsable --job-name={{job}}-shards --array=0-$((N - 1)){{partition}} --time={{time}} --cpus-per-task={{cpus}} --mem={{mem}} \
  --output="$OUT/logs/shard-%a.out" --wrap="bash '$OUT/shard.sh' \$SLURM_ARRAY_TASK_ID")
array=${array%%;*}
echo "submitted the shards: job array $array ($N tasks)"
echo "merged results will be in $OUT/runs.csv (log: $OUT/logs/merge.out)"
sbatch --parsable "${wait_flag[@]}" --job-name={{job}}-merge --dependency=afterok:$array --kill-on-invalid-dep=yes{{partition}} --time=0-00:30:00 --cpus-per-task=1 --mem={{mem}} \
  --output="$OUT/logs/merge.out" --wrap="bash '$OUT/merge.sh'"
