#!/usr/bin/env bash
# Written by `refract sweep plan --engine {{engine}}` for {{name}} ({{n}} shards): {{what}}
set -euo pipefail
built={{refract}}
REFRACT="${REFRACT:-$built}"  # another binary: REFRACT=/path/to/refract bash ...
FILE={{file}}
OUT={{out}}
N={{n}}
# Paths in the experiment file are relative to the folder the plan was made in.
cd {{workdir}}
