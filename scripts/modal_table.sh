#!/usr/bin/env bash
# Natural frequencies of every Nishida preset by modal analysis (joints held linear):
# prints the table and writes it to models/natural_frequencies.csv. Builds first.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bash "$root/scripts/build.sh" > /dev/null
table="$root/models/natural_frequencies.csv"
echo "model,subdivision,first_x_hz,first_y_hz,first_z_hz" > "$table.tmp"
for m in a b c d e f; do
  line=$("$root/build/apps/ishibashi" modal "$root/models/nishida_$m.toml" --out "$root/out/nishida_${m}_modal" | tee /dev/stderr |
         grep "first natural frequency")
  sub=$("$root/build/apps/ishibashi" modal "$root/models/nishida_$m.toml" --modes 1 --out "$root/out/nishida_${m}_modal" |
        sed -n 's/.*(subdivision \([0-9]*\)).*/\1/p')
  read -r fx fy fz < <(echo "$line" | sed -E 's/.*x ([0-9.]+) Hz, y ([0-9.]+) Hz, z ([0-9.]+) Hz.*/\1 \2 \3/')
  echo "nishida_$m,$sub,$fx,$fy,$fz" >> "$table.tmp"
done
mv "$table.tmp" "$table"
column -s, -t "$table"
