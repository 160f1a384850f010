#!/usr/bin/env bash
# `make downstream` (part of `make test`): install rodkit into a temporary
# prefix as a packager would (`make install PREFIX=…`), check the shared
# library's soname chain and what ships, then build and run the C, C++ and
# Fortran projects beside this script against it with plain CMake
# (find_package(rodkit), after moving the prefix: the package is
# relocatable) and with pkg-config, shared and static. Each program checks
# the library's version against its header or module and computed numbers
# against closed forms, and exits non-zero on a mismatch. Nothing outside
# the temporary prefix is searched (no package registry, no system
# pkg-config path), so another rodkit installed on the machine cannot stand
# in for this one.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "downstream: $*" >&2; exit 1; }
abi="$(sed -n 's/^pub const ABI_VERSION: i32 = \([0-9]*\);/\1/p' "$root/src/version.rs")"
version="$(sed -n 's/^version = "\(.*\)"/\1/p' "$root/Cargo.toml" | head -n 1)"
: "${abi:?no ABI version in src/version.rs}" "${version:?no version in Cargo.toml}"
real="librodkit.so.$abi.${version#*.}"
cc="${CC:-cc}"
fc="${FC:-gfortran}"

prefix="$work/prefix"
make -C "$root" --no-print-directory -s install PREFIX="$prefix" DESTDIR= >/dev/null
lib="$prefix/lib"

# The soname chain: librodkit.so -> librodkit.so.<ABI> -> the real file,
# whose SONAME is librodkit.so.<ABI>.
[ "$(readlink "$lib/librodkit.so")" = "librodkit.so.$abi" ] || fail "librodkit.so does not link to librodkit.so.$abi"
[ "$(readlink "$lib/librodkit.so.$abi")" = "$real" ] || fail "librodkit.so.$abi does not link to $real"
dynamic="$(readelf -d "$lib/$real")"
soname="$(sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p' <<<"$dynamic")"
[ "$soname" = "librodkit.so.$abi" ] || fail "SONAME is '$soname', not librodkit.so.$abi"
echo "downstream: $real, SONAME $soname"
# What ships beside it: the physics reference the header cites, licences,
# citation, changelog; the Fortran module where Debian keeps gfortran's.
for f in physics.md LICENSE-MIT LICENSE-APACHE CITATION.cff CHANGELOG.md; do
  [ -s "$prefix/share/doc/rodkit/$f" ] || fail "share/doc/rodkit/$f not installed"
done
ls "$lib"/fortran/gfortran-mod-*/rodkit.mod >/dev/null || fail "rodkit.mod not installed"

# pkg-config (before the prefix moves: .pc files hold absolute paths):
# shared (rpath to the prefix), static (the archive and Libs.private), the
# Fortran module's package.
export PKG_CONFIG_LIBDIR="$lib/pkgconfig"
unset PKG_CONFIG_PATH
pkg-config --exact-version="$version" rodkit rodkit-fortran || fail "pkg-config does not report $version"
"$cc" -std=c11 "$here/c/main.c" $(pkg-config --cflags --libs rodkit) -lm -Wl,-rpath,"$lib" -o "$work/pc_c"
"$cc" -std=c11 "$here/c/main.c" $(pkg-config --cflags rodkit) "$lib/librodkit.a" \
  $(pkg-config --static --libs-only-l rodkit | sed 's/-lrodkit //') -lm -o "$work/pc_c_static"
"$fc" "$here/fortran/main.f90" $(pkg-config --cflags --libs rodkit-fortran) -Wl,-rpath,"$lib" -o "$work/pc_fortran"
for exe in pc_c pc_c_static pc_fortran; do
  printf 'pkg-config %-23s ' "$exe:"
  "$work/$exe"
done

# CMake, from the prefix moved elsewhere: each project configured against
# it alone, built, run.
mv "$prefix" "$work/moved"
prefix="$work/moved"
lib="$prefix/lib"
cmake_args=(-Drodkit_DIR="$lib/cmake/rodkit" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_BUILD_TYPE=Release)
for project in c cpp fortran; do
  cmake -S "$here/$project" -B "$work/build-$project" "${cmake_args[@]}" >/dev/null
  cmake --build "$work/build-$project" >/dev/null
done
for exe in c/downstream_c c/downstream_c_static cpp/downstream_cpp cpp/downstream_cpp_static fortran/downstream_fortran; do
  printf 'cmake %-28s ' "$exe:"
  "$work/build-${exe%%/*}/${exe#*/}"
done
# The shared programs load the soname, not the unversioned name; the static
# ones need no librodkit at run time.
for exe in c/downstream_c cpp/downstream_cpp fortran/downstream_fortran; do
  needed="$(readelf -d "$work/build-${exe%%/*}/${exe#*/}" | sed -n 's/.*(NEEDED).*\[\(librodkit[^]]*\)\]/\1/p')"
  [ "$needed" = "librodkit.so.$abi" ] || fail "$exe needs '$needed', not librodkit.so.$abi"
done
static_dynamic="$(readelf -d "$work/build-c/downstream_c_static" "$work/build-cpp/downstream_cpp_static")"
if grep -q 'NEEDED.*librodkit' <<<"$static_dynamic"; then fail "a static program still needs librodkit.so"; fi

# Version requests: accepted without a version, with 0.<minor> and the exact
# version, with a range around it; refused — with CMake's own reason, not
# any other failure — for the next minor of a 0.x rodkit (else the next
# major) and for another major.
major="${version%%.*}"
minor="$(echo "$version" | cut -d. -f2)"
if [ "$major" = 0 ]; then newer="0.$((minor + 1))"; else newer="$((major + 1)).0"; fi
request() {
  mkdir -p "$work/request"
  printf '%s\n' 'cmake_minimum_required(VERSION 3.19)' 'project(request NONE)' \
    "find_package(rodkit $1 REQUIRED)" > "$work/request/CMakeLists.txt"
  rm -rf "$work/build-request"
  cmake -S "$work/request" -B "$work/build-request" "${cmake_args[@]}" 2>&1
}
for ok in "" "$major.$minor" "$version" "0.0...$((major + 1)).0"; do
  request "$ok" >/dev/null || fail "find_package(rodkit $ok) refused rodkit $version"
done
for bad in "$newer" "$((major + 2)).0"; do
  out="$(request "$bad" || true)"
  grep -q "considered but not accepted" <<<"$out" || fail "find_package(rodkit $bad): $out"
done
echo "downstream: CMake (relocated prefix) and pkg-config projects built and run against $version (ABI $abi)"
