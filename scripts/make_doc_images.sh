#!/usr/bin/env bash
# Regenerates docs/img/*.png (one picture per scene) and the section 7 sweeps (docs/sweep_*.csv,
# docs/img/sweep_*.png) with bsdeform-run. Run after ./scripts/run.sh or ./scripts/test.sh.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
run="${BSDEFORM_BUILD:-$root/build}/ui/bsdeform-run"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$root/docs/img"

# scene : simulated time of the picture
shots="paper_fig2_point_force:2 paper_fig3_opposite_point_forces:2 paper_fig4_oblique_uniform:2
paper_fig5_uniform_200:2 paper_fig6_sinusoidal_degree4:2 paper_fig7_sinusoidal:2
paper_sec7_central_square:1 paper_fig9_fig12_vertical_square:1 paper_fig10_fig13_oblique_square:1
region_load:2.5 composed_scene:3 drape_over_sphere:2 pressure_bulge:3 animated_force:1.5 nonplanar_rest:3
flag:4 curtain:4 pinned_cloth:4 tube_squeeze:4 balloon:4 torus_push:4 cone:4 cloth_on_cube:3
cloth_on_cube_penalty:3 cloth_on_cone:2 cantilever_roll:12 slope_friction:1.5 cloth_on_terrain:2 rising_sphere:1.3 pressed_surfaces:3
tablecloth_slide:0.5 mat_on_knives:0.3 two_sheets:1 twisted_ribbon:2.4 cloth_through_funnel:3 curtain_live:0.3"
for shot in $shots; do
  name="${shot%%:*}"; t="${shot##*:}"
  "$run" "$root/scenes/$name.iv" --until "$t" --png-at "$t" --size 360x270 -o "$work/$name" -q
  cp "$work/$name"/frame_*.png "$root/docs/img/$name.png"
  echo "docs/img/$name.png  <-  bsdeform-run scenes/$name.iv --until $t --png-at $t --size 360x270"
done

# Engineering edges (issue 23): the static equilibrium, as `bsdeform-run --static` writes it
for name in plate_built_in plate_simply_supported cantilever; do
  "$run" "$root/scenes/$name.iv" --static --png-at 0 --size 360x270 -o "$work/$name" -q > /dev/null
  cp "$work/$name"/frame_*.png "$root/docs/img/$name.png"
  echo "docs/img/$name.png  <-  bsdeform-run scenes/$name.iv --static --png-at 0 --size 360x270"
done

# Section 7: the paper's values of omega10 and omega01, t = 1, the other weight 0.1
values="0,0.0001,0.001,0.01,0.1,0.3,0.5,1,2,5,7,10,25,50,75,100,150,200"
for w in w10 w01; do
  "$run" "$root/scenes/paper_sec7_central_square.iv" --until 1 --sweep "Surface.$w=$values" -o "$work/sweep_$w" -q
  cp "$work/sweep_$w/sweep.csv" "$root/docs/sweep_$w.csv"
  cp "$work/sweep_$w/sweep.png" "$root/docs/img/sweep_$w.png"
  echo "docs/sweep_$w.csv, docs/img/sweep_$w.png  <-  bsdeform-run scenes/paper_sec7_central_square.iv --until 1 --sweep Surface.$w=$values"
done
