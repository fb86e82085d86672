#!/bin/sh
# compile_with.sh FROM TO DROP COMMAND...: runs COMMAND with its first argument that is
# FROM replaced by TO, and without the arguments that are DROP. A target's compiler
# launcher (tests/CMakeLists.txt): CMake runs "LAUNCHER... COMPILER ARGS...", and this
# swaps the build's compiler for another one, after any launcher of its own (ccache)
# that COMMAND starts with, and leaves out an option the other compiler should not get.
# A precompiled header (-x c++-header) is first removed: CMake's GCC-style rule compiles
# it with `-include HEADER`, and clang's driver would read the old HEADER.gch for it and
# fail, its header or options having changed.
from=$1
to=$2
drop=$3
shift 3
swapped=0
header=0
output=
previous=
for arg do
  shift
  if [ "$swapped" = 0 ] && [ "$arg" = "$from" ]; then
    set -- "$@" "$to"
    swapped=1
  elif [ "$arg" != "$drop" ]; then
    set -- "$@" "$arg"
  fi
  [ "$arg" = "c++-header" ] && header=1
  [ "$previous" = "-o" ] && output=$arg
  previous=$arg
done
if [ "$header" = 1 ] && [ -n "$output" ]; then
  rm -f "$output"
fi
exec "$@"
