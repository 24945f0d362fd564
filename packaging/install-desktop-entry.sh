#!/bin/sh
# Add Across Dimensions to the desktop's application menu, for this user only.
# Run it from the unpacked folder (or anywhere: it finds the folder it sits in).
# ./install-desktop-entry.sh --remove takes the entry away again.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
apps=${XDG_DATA_HOME:-$HOME/.local/share}/applications
icons=${XDG_DATA_HOME:-$HOME/.local/share}/icons/hicolor/256x256/apps
entry=$apps/across-dimensions.desktop
if [ "${1:-}" = "--remove" ]; then
    rm -f "$entry" "$icons/across-dimensions.png"
    echo "removed $entry"
    exit 0
fi
mkdir -p "$apps" "$icons"
cp "$here/across-dimensions.png" "$icons/across-dimensions.png"
# Exec names this folder; quotes keep a folder name with spaces whole.
sed -e "s|^Exec=.*|Exec=\"$here/across-dimensions\"|" \
    -e "s|^Icon=.*|Icon=$icons/across-dimensions.png|" \
    "$here/across-dimensions.desktop" > "$entry.tmp"
chmod 755 "$entry.tmp"
mv "$entry.tmp" "$entry"
command -v update-desktop-database >/dev/null 2>&1 && update-desktop-database "$apps" >/dev/null 2>&1 || true
echo "added $entry"
