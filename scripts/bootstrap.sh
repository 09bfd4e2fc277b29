#!/usr/bin/env bash
# Install what is missing, idempotently: Debian packages, the venv, the project (editable),
# the compiled numba kernels.
# Fast when everything is already there (a dpkg query and a stamp-file check).
set -euo pipefail
cd "$(dirname "$0")/.."

debs=(python3-dolfinx python3-gmsh python3-meshio python3-h5py python3-numba python3-scipy
      python3-numpy python3-mpi4py python3-matplotlib python3-pil python3-tqdm python3-venv
      python3-dev)
missing=()
for pkg in "${debs[@]}"; do
    dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" \
        || missing+=("$pkg")
done
if ((${#missing[@]})); then
    echo "bootstrap: installing Debian packages: ${missing[*]}"
    sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
    $sudo apt-get update -q
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

venv=.venv
if [ ! -x "$venv/bin/python" ]; then
    echo "bootstrap: creating $venv from /usr/bin/python3 with system site packages"
    /usr/bin/python3 -m venv --system-site-packages "$venv"
fi
# numba compiles the yarn engine's kernels at their first call and caches them beside their
# sources; compile them here, once per environment (about 20 s of CPU), rather than in the
# first run (rve_rod/compile_kernels.py), and again when a kernel module changed since. From
# the source tree, so that it runs beside pip's install.
kernels="$venv/.kernels"
compiling=""
if [ ! -f "$kernels" ] || [ -n "$(find rve_rod -name _kernels.py -newer "$kernels")" ]; then
    echo "bootstrap: compiling the yarn engine's numba kernels (once, about 20 s)"
    PYTHONPATH="$PWD" "$venv/bin/python" -m rve_rod.compile_kernels &
    compiling=$!
fi

stamp="$venv/.installed"
if [ ! -f "$stamp" ] || [ pyproject.toml -nt "$stamp" ]; then
    echo "bootstrap: installing the project (editable) and test tools"
    log="$venv/pip.log"
    if ! { "$venv/bin/python" -m pip install --disable-pip-version-check --upgrade "pip>=23" &&
           "$venv/bin/python" -m pip install --disable-pip-version-check -e ".[test]"; } >"$log" 2>&1
    then
        cat "$log" >&2
        echo "bootstrap: pip install failed (log above, also in $log)" >&2
        exit 1
    fi
    touch "$stamp"
fi
if [ -n "$compiling" ]; then
    if ! wait "$compiling"; then
        echo "bootstrap: compiling the numba kernels failed (messages above)" >&2
        exit 1
    fi
    touch "$kernels"
fi
