#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Builds the Debian package with CPack and installs it into a throw-away root: an overlay of
# this machine's / in a private mount namespace, entered with chroot. dpkg -i, ldconfig and
# every check run there; nothing reaches the real system, and the overlay's upper layer is
# deleted at the end. Inside, with no LD_LIBRARY_PATH, PYTHONPATH or COIN_* variable set:
#   - a Coin-only program (links Coin, nothing of ours) reads a scene with our nodes: Coin's
#     dynamic node loading finds /usr/lib/libSoBSplineDeformSurface.so by itself;
#   - python3 imports the installed package and the headless examples run;
#   - bsdeform-run runs an installed scene;
#   - FreeCAD, when installed, opens an installed scene and it animates (freecad_macro.py);
#   - dpkg -r removes it all, and the Coin-only program no longer knows the nodes.
# Exit 77 (skipped) when mount namespaces or overlayfs are not available (no root).
#
#   deb_install_test.sh BUILD_DIR SOURCE_DIR COIN_ONLY_READER
set -euo pipefail
build="$1"; src="$2"; reader="$3"

if [ "$(id -u)" -ne 0 ] || ! unshare -m true 2>/dev/null; then
  echo "skipped: needs root and mount namespaces (unshare -m) for the throw-away root"
  exit 77
fi

work="$(mktemp -d /tmp/bsdeform-deb.XXXXXX)"
trap 'rm -rf "$work"' EXIT
(cd "$build" && cpack -G DEB -B "$work/package" >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; exit 1; }
deb="$(ls "$work"/package/bsdeform_*_amd64.deb)"
echo "package: $(basename "$deb"), $(du -k "$deb" | cut -f1) kB"
dpkg-deb -f "$deb" Package Version Architecture Depends

mkdir -p "$work/upper" "$work/ovl-work" "$work/root"
cp "$deb" "$work/bsdeform.deb"
cp "$reader" "$work/coin_only_reader"
cp "$src/tests/nodes/dynload_scene.iv" "$work/dynload_scene.iv"
cp "$src/tests/package/freecad_macro.py" "$work/freecad_macro.py"

cat > "$work/inside.sh" <<'INSIDE'
set -euo pipefail
cd /tmp/bsdeform-test
echo "== dpkg -i"
dpkg -i bsdeform.deb >dpkg.log 2>&1 || { cat dpkg.log; exit 1; }
dpkg -L bsdeform | grep -E "lib(bsdeform_nodes|SoBSplineDeformSurface|SoForceField)\.so|/bin/|dist-packages/bsdeform/|applications|cmake/bsdeform/bsdeformConfig.cmake$" | sort
echo "== the ld.so cache (postinst ran ldconfig)"
ldconfig -p | grep -E "bsdeform|SoBSplineDeformSurface|SoForceField" || true
echo "== a Coin-only program reads our nodes (dynamic loading, no environment)"
ldd ./coin_only_reader | grep -c bsdeform && { echo "coin_only_reader links bsdeform"; exit 1; } || true
./coin_only_reader dynload_scene.iv | tee reader.out
grep -q "known: 1, shape: 1" reader.out
echo "== python3 imports the installed package"
cd /
python3 -c "import bsdeform, os; print(bsdeform.__file__); assert bsdeform.__file__.startswith('/usr/lib/')"
cd /tmp/bsdeform-test
echo "== the installed examples"
ex=/usr/share/bsdeform/examples/python
scenes=/usr/share/bsdeform/scenes
MPLBACKEND=Agg python3 $ex/run_and_plot.py $scenes/region_load.iv --until 1 -o norm.png
MPLBACKEND=Agg python3 $ex/build_and_render.py --until 0.5 -o cloth.png 2>/dev/null
test -s norm.png && test -s cloth.png
echo "== bsdeform-run on an installed scene"
bsdeform-run $scenes/paper_fig2_point_force.iv --steps 5 -o run-out --quiet
test -s run-out/Surface.csv
test -f /usr/share/applications/bsdeform-viewer.desktop
grep -q "^Exec=bsdeform-viewer" /usr/share/applications/bsdeform-viewer.desktop
if command -v freecad >/dev/null && command -v xvfb-run >/dev/null; then
  echo "== FreeCAD opens an installed scene (dynamic loading only) and it animates"
  HOME=/tmp/bsdeform-test QTWEBENGINE_CHROMIUM_FLAGS=--no-sandbox timeout 120 \
    xvfb-run -a -s "-screen 0 1280x1024x24" freecad /tmp/bsdeform-test/freecad_macro.py >freecad.log 2>&1 || true
  cat freecad.out || { tail -20 freecad.log; exit 1; }
  grep -q "^type SoBSplineDeformSurface" freecad.out
  steps=$(sed -n 's/^steps \([0-9]*\).*/\1/p' freecad.out)
  [ "${steps:-0}" -gt 3 ] || { echo "the scene did not animate in FreeCAD"; exit 1; }
else
  echo "== FreeCAD is not installed: its check is left out"
fi
echo "== dpkg -r"
dpkg -r bsdeform >dpkg-r.log 2>&1 || { cat dpkg-r.log; exit 1; }
test ! -e /usr/lib/libSoBSplineDeformSurface.so
./coin_only_reader dynload_scene.iv | tee reader2.out || true
grep -q "read failed" reader2.out
echo "PACKAGE TEST PASSED"
INSIDE

# The namespace: / overlaid read-only below a scratch layer, the kernel file systems bound in.
unshare -m --propagation private sh -c '
  set -e
  w="$1"
  mount -t overlay overlay -o "lowerdir=/,upperdir=$w/upper,workdir=$w/ovl-work" "$w/root"
  for d in proc sys dev dev/pts; do mount --bind "/$d" "$w/root/$d"; done
  mkdir -p "$w/root/tmp/bsdeform-test"
  cp "$w/bsdeform.deb" "$w/coin_only_reader" "$w/dynload_scene.iv" "$w/inside.sh" "$w/freecad_macro.py" \
     "$w/root/tmp/bsdeform-test/"
  exec chroot "$w/root" env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin HOME=/root LANG=C.UTF-8 \
    bash /tmp/bsdeform-test/inside.sh
' sh "$work"
