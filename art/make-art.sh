#!/usr/bin/env bash
# Regenerates the committed art: puff meshes (with puffbake's generators), q ramps and the
# ambient gradient (with oiiotool from openimageio-tools). Deterministic: running it again gives
# the same files. Usage: art/make-art.sh [path/to/puffbake]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
puffbake=${1:-$here/../build/puffbake/puffbake}
q=-q

# Four default puff variations, one per mesh format the loader reads.
"$puffbake" mesh $q -g lumpy   --seed 11 --subdivisions 4 --amplitude 0.22 --frequency 1.6 --octaves 3 -o "$here/puffs/variation-1.obj"
"$puffbake" mesh $q -g cluster --seed 12 --count 5 --subdivisions 3 --spread 0.5              -o "$here/puffs/variation-2.ply"
"$puffbake" mesh $q -g lumpy   --seed 13 --subdivisions 4 --amplitude 0.3 --frequency 1.2 --octaves 2 -o "$here/puffs/variation-3.off"
"$puffbake" mesh $q -g cluster --seed 14 --count 7 --subdivisions 2 --spread 0.6 --radius-min 0.3 --radius-max 0.5 -o "$here/puffs/variation-4.stl"

# q ramps (McGuire & Fein Eq. 2, Fig. 13): 256x1, sampled with clamp-to-edge at run time.
oiiotool --create 256x1 3 --fill:color=1,1,1 128x1+128+0 -d uint8 -o "$here/ramps/two-tone.png"
oiiotool --create 256x1 3 --fill:color=0.28,0.16,0.42 90x1+0+0 --fill:color=0.92,0.52,0.22 102x1+90+0 \
         --fill:color=1,0.95,0.62 64x1+192+0 -d uint8 -o "$here/ramps/three-tone-hue.png"

# Ambient gradient K_a(x, y) (Fig. 8b): light purple at the bottom, dark blue at the top.
oiiotool --pattern fill:top=0.08,0.1,0.32:bottom=0.72,0.62,0.86 256x256 3 -d uint8 -o "$here/gradients/purple-to-blue.png"
# Dark-to-light ambient gradient (Fig. 13c): dark smoke-brown at the bottom, pale flame at the top.
oiiotool --pattern fill:top=0.98,0.86,0.55:bottom=0.22,0.07,0.05 256x256 3 -d uint8 -o "$here/gradients/dark-to-light.png"

# The plate of plate-cloud.json (Fig. 8d): a hand-drawn-looking landscape, Python standard library only.
python3 "$here/make-plate.py" "$here/plates/hills.png"
