#!/usr/bin/env bash
# Largest source files and functions (lines), from universal-ctags' end fields.
set -euo pipefail
n=${1:-10}
dirs="model raster io editor ui app bench synth"
existing=$(for d in $dirs; do if [ -d "$d" ]; then echo "$d"; fi; done)
echo "## largest files (lines)"
find $existing -name '*.cpp' -o -name '*.h' | xargs wc -l | grep -v ' total$' | sort -rn | head -n "$n"
echo "## largest functions (lines)"
ctags --fields=+ne --c++-kinds=f -R --languages=C++ -f - $existing 2>/dev/null |
  awk -F'\t' '{ln="";en=""; for(i=4;i<=NF;i++){if($i~/^line:/)ln=substr($i,6); if($i~/^end:/)en=substr($i,5)} if(ln!=""&&en!="") print en-ln+1, $2":"ln, $1}' |
  sort -rn | head -n "$n"
