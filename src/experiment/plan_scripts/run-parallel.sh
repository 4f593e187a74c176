# Extra arguments go to GNU parallel (e.g. --sshloginfile FILE, -j 1). Over
# ssh, every host must see $REFRACT and $OUT at the same paths.
mkdir -p "$OUT/logs"
parallel --will-cite --halt now,fail=1 --joblog "$OUT/logs/parallel.log" "$@" bash "$OUT/shard.sh" {} ::: $(seq 0 $((N - 1)))
bash "$OUT/merge.sh"
