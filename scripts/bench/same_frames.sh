#!/usr/bin/env bash
# Renders frames with two fovlab binaries and compares what they write byte for byte: the linear
# frame (.exr), the step heat map and the mask image. For a speed change that must keep every frame
# (and so every logged frame hash) as it was (issue 41).
#
#   scripts/bench/same_frames.sh OLD_FOVLAB NEW_FOVLAB OUT_DIR [sampling|traced|all]
#
# sampling (the default): rmfr on primitives and columns at four gazes and three sigmas (640x360),
# kfr, hyperbolic and linear at two gazes, rmfr at 1280x720 and at 4 spp, and the Lanczos read of
# rmfr, kfr and hyperbolic. traced: gt, ipr and fipr at 320x180 on primitives, columns, temple and
# wires at 1, 4 and 16 spp; ipr with the paper's ray test, min filter 3, four levels and the
# full-resolution depth level; fipr over three frames at refresh 1 and 4, traced periphery, the
# paper's edges and near misses, away from the centre. Prints one line a case and the counts; exit
# status 1 when any case differs or fails.
set -u
if (($# != 3 && $# != 4)) || [[ ${4:-sampling} != @(sampling|traced|all) ]]; then
  echo "usage: $0 OLD_FOVLAB NEW_FOVLAB OUT_DIR [sampling|traced|all]" >&2
  exit 2
fi
old=$1 new=$2 out=$3 which_cases=${4:-sampling}
mkdir -p "$out/old" "$out/new"
cases=()
small="--width 320 --height 180"
if [[ $which_cases != sampling ]]; then
  for scene in primitives columns temple wires; do
    for spp in 1 4 16; do
      for method in gt ipr fipr; do cases+=("$scene|$method|160,90|$small --spp $spp"); done
    done
    cases+=("$scene|ipr|160,90|$small --coarse-test ray --min-filter 3")
    cases+=("$scene|ipr|160,90|$small --levels 4 --spp 4")
    cases+=("$scene|ipr|160,90|$small --full-depth --spp 4")
    cases+=("$scene|fipr|40,150|$small --frames 3 --refresh 4 --spp 4")
    cases+=("$scene|fipr|250,60|$small --frames 3 --refresh 1 --periphery-steps 64 --combine fovea-or-product")
    cases+=("$scene|fipr|160,90|$small --frames 3 --refresh 2 --coarse-test ray --near-misses ignore --edge-depth level")
  done
fi
[[ $which_cases == traced ]] || for scene in primitives columns; do
  for gaze in "320,180" "40,300" "600,20" "213.7,91.3"; do
    for sigma in 2.6 1.5 4; do cases+=("$scene|rmfr|$gaze|--sigma $sigma"); done
  done
  for gaze in "320,180" "40,300"; do
    for method in kfr hyperbolic linear; do cases+=("$scene|$method|$gaze|"); done
  done
done
if [[ $which_cases != traced ]]; then
  cases+=("primitives|rmfr|640,360|--sigma 2.6 --width 1280 --height 720")
  cases+=("primitives|rmfr|320,180|--sigma 2.6 --spp 4")
  for method in rmfr kfr hyperbolic; do
    cases+=("primitives|$method|320,180|--resample lanczos")
    cases+=("columns|$method|40,300|--resample lanczos")
  done
fi
same=0 differ=0
for case in "${cases[@]}"; do
  IFS='|' read -r scene method gaze extra <<<"$case"
  size=(--width 640 --height 360)
  [[ "$extra" == *--width* ]] && size=()
  name=$(echo "$scene $method $gaze $extra" | tr -s ' ,.' '_')
  ok=1
  files=("$name.exr" "$name.steps.png")
  [[ $method == @(gt|ipr) ]] || files+=("$name.mask.png")  # gt and ipr have no mask
  for which in old new; do
    mask=()
    [[ $method == @(gt|ipr) ]] || mask=(--mask-out "$out/$which/$name.mask.png")
    binary=$old
    [[ $which == new ]] && binary=$new
    # shellcheck disable=SC2086  # $extra is a list of flags
    if ! "$binary" render --scene "$scene" --method "$method" "${size[@]}" --gaze "$gaze" $extra \
      --out "$out/$which/$name.exr" --steps-out "$out/$which/$name.steps.png" "${mask[@]}" \
      >"$out/$which/$name.log" 2>&1; then
      ok=0
      echo "FAILED $which $name (log: $out/$which/$name.log)"
    fi
  done
  for file in "${files[@]}"; do
    cmp -s "$out/old/$file" "$out/new/$file" || ok=0
  done
  if ((ok)); then
    same=$((same + 1))
    echo "same    $name  sha256 $(sha256sum <"$out/new/$name.exr" | cut -c1-16)"
  else
    differ=$((differ + 1))
    echo "DIFFERS $name"
  fi
done
echo "identical: $same, differing or failed: $differ"
((differ == 0))
