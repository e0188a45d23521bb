# Sourced by the benchmarks: nordland_folder NORDLAND_DIR OUT_DIR makes OUT_DIR/frames, Nordland summer then
# winter as one folder of 3,600 frames (links), and OUT_DIR/poses.csv, frame k of either season at (k mod 1800, 0),
# the ground truth of seqtopo map --ground-truth OUT_DIR/poses.csv --gt-radius 2.
nordland_folder() {
  local nordland=$1 out=$2 k=0 season f
  mkdir -p "$out/frames"
  for season in summer winter; do
    for f in $(ls "$nordland/$season" | sort); do
      ln -sf "$(realpath "$nordland/$season/$f")" "$out/frames/$(printf %04d $k).png"
      k=$((k + 1))
    done
  done
  python3 -c "
print('index,x,y,theta')
for k in range(3600): print(f'{k},{k % 1800},0,0')" > "$out/poses.csv"
}
