#!/usr/bin/env bash
# Unpacks LinuxCNC's standalone interpreter `rs274` from Debian's packages into DEST without
# installing LinuxCNC, and writes DEST/rs274, a wrapper that sets the library path. The
# differential tests (tests/gcode/rs274_differential_test.cpp) run it as their oracle.
#   tools/rs274/fetch.sh build/rs274
set -euo pipefail
dest=$(mkdir -p "${1:?usage: fetch.sh DEST}" && cd "$1" && pwd)
# Unpacked before: nothing to download (rs274 -h exits 1, so its binary is what is checked).
if [ -x "$dest/rs274" ] && [ -x "$dest/root/usr/bin/rs274" ]; then exit 0; fi
mkdir -p "$dest/debs" "$dest/root"
(cd "$dest/debs" && apt-get download linuxcnc-uspace libboost-python1.74.0 >/dev/null)
for deb in "$dest"/debs/*.deb; do dpkg -x "$deb" "$dest/root"; done
cat > "$dest/rs274" <<WRAP
#!/usr/bin/env bash
export LD_LIBRARY_PATH="$dest/root/usr/lib:$dest/root/usr/lib/x86_64-linux-gnu\${LD_LIBRARY_PATH:+:\$LD_LIBRARY_PATH}"
exec "$dest/root/usr/bin/rs274" "\$@"
WRAP
chmod +x "$dest/rs274"
echo "rs274 unpacked in $dest"
