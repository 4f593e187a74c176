i="${1:?usage: shard.sh I [--resume]}"
shift
exec "$REFRACT" sweep "$FILE"{{quick}} --shard "$i/$N" --out "$OUT/shards/$i" "$@"
