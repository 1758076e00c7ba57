# tests/need_python.sh — sourced by the scripts that read their results with Debian's Python
# modules: `need_python MODULE PACKAGE` sets PY to /usr/bin/python3 (Debian's, with its
# python3-* packages) and skips the test (exit 77) when it cannot import MODULE.
need_python() {
  PY=/usr/bin/python3
  if ! [ -x "$PY" ] || ! "$PY" -c "import $1" >/dev/null 2>&1; then
    echo "skipped: /usr/bin/python3 cannot import $1 (apt-get install $2)"
    exit 77
  fi
}
