#!/bin/sh
# AUTO-07p peer runs for the rodkit benchmarks (see README.md in this directory).
#
#   run.sh check                                  exit 0 iff AUTO-07p and gfortran are usable
#   run.sh build   BUILD_DIR                      compile follower.exe, dead.exe and euler.exe once (cached:
#                                                 rebuilt only when a source is newer)
#   run.sh prepare PROBLEM WORK_DIR NTST TOL      write the constants file(s) into WORK_DIR
#   run.sh run     PROBLEM BUILD_DIR WORK_DIR NTST TOL
#                                                 build + prepare + run, print the wall time of the
#                                                 executable(s) alone and the labelled points
# PROBLEM is follower, dead or euler. NCOL = 4 unless AUTO_NCOL says. TOL sets EPSL = EPSU = TOL and EPSS = 10 TOL.
# Overrides (environment): AUTO_NCOL (collocation points, default 4), AUTO_IAD (mesh adaption, default 3), AUTO_DSMAX (default 0.5),
# AUTO_ITNW (default 7), AUTO_EPSS (default 10*TOL), AUTO_DIR (default /usr/lib/auto-07p).
# Outputs in WORK_DIR: fort.7 (b-file), fort.8 (s-file), fort.9 (diagnostics); for euler the first
# run's files are kept as b.euler1, s.euler1 (restart file of run 2), d.euler1.
set -eu

HERE=$(cd "$(dirname "$0")" && pwd)
AUTO_DIR=${AUTO_DIR:-/usr/lib/auto-07p}
export OMP_NUM_THREADS=1

die() { echo "run.sh: $*" >&2; exit 2; }

# Compiler and flags exactly as AUTO's own cmds/cmds.make (FC, FFLAGS, OPT).
makevar() {
    sed -n "s/^$1[[:space:]]*=[[:space:]]*//p" "$AUTO_DIR/cmds/cmds.make" | head -n 1
}

check() {
    [ -d "$AUTO_DIR/lib" ] || { echo "AUTO-07p not found in $AUTO_DIR (apt-get install auto-07p)"; return 1; }
    ls "$AUTO_DIR"/lib/*.o >/dev/null 2>&1 || { echo "no AUTO-07p objects in $AUTO_DIR/lib"; return 1; }
    FC=$(makevar FC); FC=${FC:-gfortran}
    command -v "$FC" >/dev/null 2>&1 || { echo "Fortran compiler $FC not found"; return 1; }
    return 0
}

build() {
    bdir=$1
    check >&2 || exit 1
    mkdir -p "$bdir"
    FC=$(makevar FC); FFLAGS=$(makevar FFLAGS); OPT=$(makevar OPT)
    # dead.exe: follower.f90 with the dead tip force (-DDEAD_LOAD).
    for p in follower dead euler; do
        exe="$bdir/$p.exe"
        src=$p; defs=""
        [ "$p" = dead ] && { src=follower; defs="-DDEAD_LOAD"; }
        if [ ! -x "$exe" ] || [ "$HERE/$src.f90" -nt "$exe" ] || [ "$HERE/rod_common.inc" -nt "$exe" ]; then
            # shellcheck disable=SC2086
            $FC $FFLAGS $OPT -cpp $defs -I"$HERE" -c "$HERE/$src.f90" -o "$bdir/$p.o"
            # shellcheck disable=SC2086
            $FC $FFLAGS $OPT "$bdir/$p.o" -o "$exe.tmp" "$AUTO_DIR"/lib/*.o
            mv "$exe.tmp" "$exe"
            echo "built $exe" >&2
        fi
    done
}

subst() { # template ntst tol
    tol=$3
    epss=${AUTO_EPSS:-$(awk -v t="$tol" 'BEGIN { printf "%.3g", 10 * t }')}
    sed -e "s/@NTST@/$2/" -e "s/@NCOL@/${AUTO_NCOL:-4}/" -e "s/@IAD@/${AUTO_IAD:-3}/" -e "s/@ITNW@/${AUTO_ITNW:-7}/" \
        -e "s/@EPSL@/$tol/" -e "s/@EPSU@/$tol/" -e "s/@EPSS@/$epss/" \
        -e "s/@DSMAX@/${AUTO_DSMAX:-0.5}/" -e "s/@IRS@/'BP1'/" "$1"
}

prepare() { # problem workdir ntst tol
    mkdir -p "$2"
    case $1 in
        follower) subst "$HERE/c.follower.in" "$3" "$4" > "$2/c.follower" ;;
        dead) subst "$HERE/c.dead.in" "$3" "$4" > "$2/c.dead" ;;
        euler) subst "$HERE/c.euler.1.in" "$3" "$4" > "$2/c.euler.1"
               subst "$HERE/c.euler.2.in" "$3" "$4" > "$2/c.euler.2" ;;
        *) die "unknown problem $1" ;;
    esac
}

now_ns() { date +%s%N; }

runexe() { # exe constants -> prints elapsed seconds of the executable alone
    t0=$(now_ns)
    "$1" < "$2" > stdout.txt
    t1=$(now_ns)
    awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.6f\n", (b - a) / 1e9 }'
}

run() { # problem builddir workdir ntst tol
    build "$2"
    prepare "$1" "$3" "$4" "$5"
    bdir=$(cd "$2" && pwd)
    cd "$3"
    rm -f fort.7 fort.8 fort.9 b.euler1 s.euler1 d.euler1
    case $1 in
        follower)
            t=$(runexe "$bdir/follower.exe" c.follower)
            echo "follower NTST=$4 TOL=$5 time_s=$t" ;;
        dead)
            t=$(runexe "$bdir/dead.exe" c.dead)
            echo "dead NTST=$4 TOL=$5 time_s=$t" ;;
        euler)
            t1=$(runexe "$bdir/euler.exe" c.euler.1)
            mv fort.7 b.euler1; mv fort.8 s.euler1; mv fort.9 d.euler1
            t2=$(runexe "$bdir/euler.exe" c.euler.2)
            echo "euler NTST=$4 TOL=$5 time_s=$t1+$t2" ;;
    esac
    # labelled points (TY: 6 = BP of a BVP, -4 = UZ, 9 = EP; 4 = labelled regular point)
    for f in b.euler1 fort.7; do
        [ -f "$f" ] && awk '$1 != 0 && $4 != 0' "$f"
    done
    return 0
}

cmd=${1:-}
[ $# -gt 0 ] && shift
case $cmd in
    check) check ;;
    build) [ $# -eq 1 ] || die "usage: run.sh build BUILD_DIR"; build "$1" ;;
    prepare) [ $# -eq 4 ] || die "usage: run.sh prepare PROBLEM WORK_DIR NTST TOL"; prepare "$@" ;;
    run) [ $# -eq 5 ] || die "usage: run.sh run PROBLEM BUILD_DIR WORK_DIR NTST TOL"; run "$@" ;;
    *) die "usage: run.sh check | build DIR | prepare PROBLEM DIR NTST TOL | run PROBLEM BUILD_DIR WORK_DIR NTST TOL" ;;
esac
