#!/usr/bin/env bash
# Gets the real models the course measures on (chapter 07's benchmark set and a few classics)
# into models/, or checks copies you already have:
#   tools/get-models.sh                  download, convert and check each one
#   tools/get-models.sh --from DIR       check DIR/NAME.obj.gz (no network) and link them in
#   tools/get-models.sh --list           the models, their sources and their terms
#   tools/get-models.sh --help           every option
# The work is done by tools/models.py (Python's standard library only).
set -euo pipefail
exec python3 "$(dirname "$0")/models.py" "$@"
