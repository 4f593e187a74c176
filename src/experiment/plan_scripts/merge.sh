shards=()
for i in $(seq 0 $((N - 1))); do shards+=("$OUT/shards/$i"); done
exec "$REFRACT" sweep merge "${shards[@]}" --out "$OUT" --experiment "$FILE"{{quick}} "$@"
