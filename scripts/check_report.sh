#!/usr/bin/env bash
# Render a design report in headless Chromium and save a screenshot to look at.
#   scripts/check_report.sh [DESIGN.toml] [OUT_DIR]
# Needs Debian's chromium (apt-get install chromium). Writes OUT_DIR/<name>.html and
# OUT_DIR/<name>.png (full width, 1280 x 4000 px of the page, scripts run: plotly drawn).
set -euo pipefail
design="${1:-examples/nutation_double_sided.toml}"
out="${2:-report-check}"
here="$(cd "$(dirname "$0")/.." && pwd)"
bin="$here/.venv/bin"
browser="$(command -v chromium || command -v chromium-browser || true)"
if [ -z "$browser" ]; then
    echo "check_report: chromium not found (Debian: apt-get install chromium)" >&2
    exit 2
fi
mkdir -p "$out"
name="$(basename "$design" .toml)"
html="$out/$name.html"
png="$out/$name.png"
MPLBACKEND=Agg "$bin/reducerlab" report "$design" -o "$html"
"$browser" --headless=new --no-sandbox --disable-gpu --hide-scrollbars \
    --window-size=1280,${HEIGHT:-4000} --virtual-time-budget=15000 \
    --screenshot="$png" "file://$(cd "$(dirname "$html")" && pwd)/$(basename "$html")" \
    >/dev/null 2>&1
test -s "$png"
echo "screenshot: $png"
