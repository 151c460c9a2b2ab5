#!/usr/bin/env bash
# The README's test command: every Rust test, then the Python package built and tested in a
# virtualenv under the target directory. Needs the Rust toolchain, python3 (≥ 3.9, with venv) and
# access to PyPI. `.ci/run` calls it.
#
#   tools/test.sh
#
# The Python build shares cargo's target directory, so maturin reuses what `cargo test` built
# (crates/tumble-py/Cargo.toml keeps the dependency features the same).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$ROOT/target}"
PYTHON="${PYTHON:-python3}"

echo "== cargo test --release --workspace"
cargo test --release --workspace

echo "== Python: virtualenv, tools, the package (pip install crates/tumble-py)"
VENV="$CARGO_TARGET_DIR/venv"
if [ ! -x "$VENV/bin/python" ]; then
    "$PYTHON" -m venv "$VENV"
fi
PY="$VENV/bin/python"
"$PY" -m pip install --quiet --disable-pip-version-check --upgrade pip
"$PY" -m pip install --quiet --disable-pip-version-check maturin pytest numpy gymnasium ray mypy
# the README's install line; --force-reinstall: the same version number may hold older code
"$PY" -m pip install --disable-pip-version-check --force-reinstall --no-deps crates/tumble-py

echo "== pytest"
export TUMBLE_CLI="$CARGO_TARGET_DIR/release/tumble"   # built by cargo test (the CLI's tests run it)
export RAY_USAGE_STATS_ENABLED=0
# from the tests' directory, so that `import tumble` is the installed package, not the sources
status=0
(cd crates/tumble-py/tests && "$PY" -m pytest -q -p no:cacheprovider) || status=$?
if [ "$status" -eq 5 ]; then
    echo "error: pytest collected no test" >&2
    exit 1
elif [ "$status" -ne 0 ]; then
    exit "$status"
fi

echo "== stubtest: the .pyi stubs against the module"
(cd crates/tumble-py/tests && MYPY_CACHE_DIR="$CARGO_TARGET_DIR/mypy_cache" "$PY" -m mypy.stubtest tumble)
echo "== all tests passed"
