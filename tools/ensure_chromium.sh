#!/bin/sh
# Install Debian's chromium for the browser and JupyterLab tests when /usr/bin/chromium is absent.
# Without apt-get or root it only says so; those tests then skip with that reason.
#
#   sh tools/ensure_chromium.sh          install now (if needed), in the foreground
#   sh tools/ensure_chromium.sh --start  begin it in the background, its output in
#                                        _build/chromium-install.log (make test: beside the
#                                        unit tests, which need no browser; about 90 s of apt)
#   sh tools/ensure_chromium.sh --wait   wait for a background install, show its lines, then
#                                        check (and install) as without an option
LOG=_build/chromium-install.log
PID=_build/chromium-install.pid
case "${1:-}" in
    --start)
        if [ -x /usr/bin/chromium ] || [ -n "${XNAVLAB_CHROMIUM:-}" ]; then
            exit 0
        fi
        mkdir -p _build
        sh "$0" > "$LOG" 2>&1 &
        echo $! > "$PID"
        echo "browser-test: installing Debian's chromium in the background (log: $LOG)" >&2
        exit 0
        ;;
    --wait)
        if [ -f "$PID" ]; then
            pid=$(cat "$PID")
            while kill -0 "$pid" 2>/dev/null; do sleep 1; done
            rm -f "$PID"
            grep '^browser-test:\|^E:' "$LOG" >&2
        fi
        exec sh "$0"
        ;;
esac
if [ -x /usr/bin/chromium ] || [ -n "${XNAVLAB_CHROMIUM:-}" ]; then
    exit 0
fi
if ! command -v apt-get >/dev/null 2>&1; then
    echo "browser-test: /usr/bin/chromium is missing and apt-get is unavailable: the browser test will be SKIPPED" >&2
    exit 0
fi
if [ "$(id -u)" != 0 ]; then
    echo "browser-test: /usr/bin/chromium is missing and installing it needs root: the browser test will be SKIPPED" >&2
    exit 0
fi
echo "browser-test: installing Debian's chromium (apt-get)" >&2
apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium \
    && echo "browser-test: chromium installed" >&2
