#!/bin/sh
# `make pythons`: the unit tests, doctests and notebooks (`make unit`, `make notebooks`) under
# every supported Python found on this machine, each in its own environment _build/venv-3.X
# (under _build, which git, pytest, ruff and the book's Sphinx already leave alone), one after
# another. Prints which versions it skipped (not found) and, per version, the passed / failed /
# skipped counts of both pytest runs and the wall time of the set-up (venv, packages, warm-up)
# and of the tests; each version's whole output goes to _build/pythons-3.X.log.
#
# Usage: sh tools/pythons.sh RANGE [MAKE]   (RANGE as requires-python: ">=3.10,<3.14")
# A Python 3.X is looked for as python3.X on PATH, then as the newest pyenv version 3.X.*
# ($PYENV_ROOT, default ~/.pyenv); each candidate is run to check it is 3.X (a pyenv shim of a
# version not selected is not). Exit status 1 when any version failed or none was found.
set -u
range=$1
make=${2:-make}
lo=${range#*>=}; lo=${lo%%,*}     # 3.10
hi=${range#*<}; hi=${hi%%,*}      # 3.14 (excluded)
major=${lo%%.*}
minor=${lo#*.}
stop=${hi#*.}
pyenv_root=${PYENV_ROOT:-$HOME/.pyenv}
mkdir -p _build

is_version() {  # is_version PYTHON 3.X: the interpreter runs and is 3.X
    [ "$("$1" -c 'import sys; print("%d.%d" % sys.version_info[:2])' 2>/dev/null)" = "$2" ]
}

find_python() {  # find_python 3.X: the path of a working Python 3.X, or nothing
    found=$(command -v "python$1" 2>/dev/null)
    if [ -n "$found" ] && is_version "$found" "$1"; then
        echo "$found"
        return
    fi
    for patch in $(ls "$pyenv_root/versions" 2>/dev/null | grep -E "^$1\.[0-9]+\$" | sort -t. -k3,3nr); do
        found=$pyenv_root/versions/$patch/bin/python3
        if is_version "$found" "$1"; then
            echo "$found"
            return
        fi
    done
}

counts() {  # counts LOG: "passed N, failed N, skipped N[, errors N]" summed over its pytest runs
    grep -E '^=+ .*[0-9]+ (passed|failed|skipped|errors?).* in [0-9.]+s' "$1" | awk '
        { for (i = 2; i <= NF; i++) { w = $i; sub(/,$/, "", w)
              if (w == "passed" || w == "failed" || w == "skipped") n[w] += $(i - 1)
              if (w == "error" || w == "errors") n["errors"] += $(i - 1) } }
        END { printf "passed %d, failed %d, skipped %d", n["passed"], n["failed"], n["skipped"]
              if (n["errors"]) printf ", errors %d", n["errors"] }'
}

report=""
status=0
tested=0
while [ "$minor" -lt "$stop" ]; do
    v=$major.$minor
    minor=$((minor + 1))
    py=$(find_python "$v")
    # the interpreter itself, not a pyenv shim in front of it
    [ -z "$py" ] || py=$("$py" -c 'import sys; print(sys.executable)')
    if [ -z "$py" ]; then
        echo "pythons: $v skipped (not found: no python$v on PATH, none under $pyenv_root/versions)"
        report="$report
$v  skipped (not found)"
        continue
    fi
    tested=$((tested + 1))
    log=_build/pythons-$v.log
    full=$("$py" -c 'import sys; print(sys.version.split()[0])')
    echo "pythons: $full ($py) in _build/venv-$v, log $log"
    args="--no-print-directory VENV=_build/venv-$v PYTHON=$py"
    t0=$(date +%s)
    $make $args warmup >"$log" 2>&1
    setup_rc=$?
    t1=$(date +%s)
    if [ "$setup_rc" = 0 ]; then
        $make $args unit >>"$log" 2>&1
        unit_rc=$?
        $make $args notebooks >>"$log" 2>&1
        nb_rc=$?
    else
        unit_rc=1; nb_rc=1
    fi
    t2=$(date +%s)
    tally=$(counts "$log")
    if [ "$setup_rc" != 0 ]; then
        result="FAILED in the set-up (see $log)"
    elif [ "$unit_rc" = 0 ] && [ "$nb_rc" = 0 ] && [ "${tally#passed 0,}" = "$tally" ] \
         && [ "${tally#*failed 0,}" != "$tally" ] && [ "${tally#*errors}" = "$tally" ]; then
        result="green"
    else
        result="FAILED (unit exit $unit_rc, notebooks exit $nb_rc; see $log)"
    fi
    [ "$result" = green ] || status=1
    line="$full  $result ($tally); set-up $((t1 - t0)) s, tests $((t2 - t1)) s"
    echo "pythons: $line"
    report="$report
$line"
done
echo "pythons: supported $range; results (unit tests and doctests, then the notebooks):$report"
if [ "$tested" = 0 ]; then
    echo "pythons: no supported Python found: nothing tested" >&2
    exit 1
fi
exit $status
