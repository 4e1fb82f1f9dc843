#!/bin/sh
# Install Debian's chromium for `make browser-test` when /usr/bin/chromium is absent.
# Without apt-get or root it only says so; the browser test then skips with that reason.
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
apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium
