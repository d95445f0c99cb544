#!/usr/bin/env bash
# Opens a .glb export in three.js (GLTFLoader, WebGL through SwiftShader in headless Chromium)
# as a web page would, with the file's own camera, and prints what three.js read: meshes,
# cameras, the scene's bounds (metres) and the camera's position, view direction and field of
# view. The rendered view goes to OUT.png.
#
# Usage: benches/threejs/open.sh lit.glb OUT.png     (needs node/npm and Debian's chromium)
set -euo pipefail
glb=$(realpath "$1") out=$(realpath -m "$2")
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d)
trap 'kill "$server" 2>/dev/null; rm -rf "$work"' EXIT
(cd "$work" && npm install --silent three@0.170.0 > /dev/null)
cp "$here/page.html" "$work/" && cp "$glb" "$work/model.glb"
port=$((20000 + RANDOM % 20000))
(cd "$work" && exec python3 -m http.server "$port" > /dev/null 2>&1) &
server=$!
sleep 1
flags=(--headless --no-sandbox --disable-gpu --use-angle=swiftshader --enable-unsafe-swiftshader
       --virtual-time-budget=5000 --window-size=512,512)
url="http://localhost:$port/page.html?f=model.glb"
chromium "${flags[@]}" --screenshot="$out" "$url" 2> /dev/null
chromium "${flags[@]}" --dump-dom "$url" 2> /dev/null | sed -nE 's|.*<pre id="facts">([^<]*).*|\1|p'
