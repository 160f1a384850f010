#!/usr/bin/env bash
# `make downstream` (part of `make test`): install rodkit into a temporary
# prefix as a packager would (`make install PREFIX=…`), check the shared
# library's soname chain, then build and run the C, C++ and Fortran projects
# beside this script against it with plain CMake (find_package(rodkit)) and
# with pkg-config, shared and static. Each program checks the library's
# version against its header or module and computed numbers against closed
# forms, and exits non-zero on a mismatch.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
abi="$(sed -n 's/^pub const ABI_VERSION: i32 = \([0-9]*\);/\1/p' "$root/src/version.rs")"
version="$(sed -n 's/^version = "\(.*\)"/\1/p' "$root/Cargo.toml" | head -n 1)"
real="librodkit.so.$abi.${version#*.}"

make -C "$root" --no-print-directory -s install PREFIX="$prefix" >/dev/null

# The soname chain: librodkit.so -> librodkit.so.<ABI> -> the real file,
# whose SONAME is librodkit.so.<ABI>.
lib="$prefix/lib"
[ "$(readlink "$lib/librodkit.so")" = "librodkit.so.$abi" ] || { echo "librodkit.so does not link to librodkit.so.$abi" >&2; exit 1; }
[ "$(readlink "$lib/librodkit.so.$abi")" = "$real" ] || { echo "librodkit.so.$abi does not link to $real" >&2; exit 1; }
soname="$(readelf -d "$lib/$real" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')"
[ "$soname" = "librodkit.so.$abi" ] || { echo "SONAME is '$soname', not librodkit.so.$abi" >&2; exit 1; }
echo "downstream: $real, SONAME $soname"
# What ships beside it: the physics reference the header cites, licences,
# citation, changelog.
for f in physics.md LICENSE-MIT LICENSE-APACHE CITATION.cff CHANGELOG.md; do
  [ -s "$prefix/share/doc/rodkit/$f" ] || { echo "share/doc/rodkit/$f not installed" >&2; exit 1; }
done

# CMake: each project configured against the prefix only, built, run.
for project in c cpp fortran; do
  cmake -S "$here/$project" -B "$work/build-$project" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$work/build-$project" >/dev/null
done
for exe in c/downstream_c c/downstream_c_static cpp/downstream_cpp cpp/downstream_cpp_static fortran/downstream_fortran; do
  printf 'cmake %-28s ' "$exe:"
  "$work/build-${exe%%/*}/${exe#*/}"
done
# The shared programs load the soname, not the unversioned name.
needed="$(readelf -d "$work/build-c/downstream_c" | sed -n 's/.*(NEEDED).*\[\(librodkit[^]]*\)\]/\1/p')"
[ "$needed" = "librodkit.so.$abi" ] || { echo "downstream_c needs '$needed', not librodkit.so.$abi" >&2; exit 1; }
# The static ones need no librodkit at run time.
if readelf -d "$work/build-c/downstream_c_static" "$work/build-cpp/downstream_cpp_static" | grep -q 'NEEDED.*librodkit'; then
  echo "a static downstream program still needs librodkit.so" >&2; exit 1
fi
# A request for an incompatible version (the next minor of a 0.x rodkit,
# else the next major) is refused.
major="${version%%.*}"
minor="$(echo "$version" | cut -d. -f2)"
if [ "$major" = 0 ]; then request="0.$((minor + 1))"; else request="$((major + 1)).0"; fi
mkdir -p "$work/too-new"
printf '%s\n' 'cmake_minimum_required(VERSION 3.16)' 'project(too_new C)' \
  "find_package(rodkit $request REQUIRED)" > "$work/too-new/CMakeLists.txt"
if cmake -S "$work/too-new" -B "$work/build-too-new" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null 2>&1; then
  echo "find_package(rodkit $request) accepted rodkit $version" >&2; exit 1
fi

# pkg-config: shared (rpath to the prefix), static (the archive and
# Libs.private), and the Fortran module's package.
export PKG_CONFIG_PATH="$lib/pkgconfig"
cc -std=c11 "$here/c/main.c" $(pkg-config --cflags --libs rodkit) -lm -Wl,-rpath,"$lib" -o "$work/pc_c"
cc -std=c11 "$here/c/main.c" $(pkg-config --cflags rodkit) "$lib/librodkit.a" \
  $(pkg-config --static --libs-only-l rodkit | sed 's/-lrodkit //') -lm -o "$work/pc_c_static"
gfortran "$here/fortran/main.f90" $(pkg-config --cflags --libs rodkit-fortran) -Wl,-rpath,"$lib" -o "$work/pc_fortran"
for exe in pc_c pc_c_static pc_fortran; do
  printf 'pkg-config %-23s ' "$exe:"
  "$work/$exe"
done
echo "downstream: CMake and pkg-config projects built and run against $version (ABI $abi)"
