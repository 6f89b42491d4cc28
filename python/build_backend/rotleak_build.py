"""The PEP 517 build backend of rotleak's Python package: ``pip install .`` from the repository's root.

It lets CMake build the package exactly as the project's own build does (the in-process module
_rotleak with pybind11, the package's files and its _version.py into BUILD/python/rotleak) and packs that
directory into a wheel. It uses the standard library only, so that pip's isolated build environment
needs nothing from the network (scikit-build, Debian's python3-skbuild, would have to be installed into
that environment from PyPI: there is no network here). The wheel is platform-specific (the module is
compiled) and its dependencies, numpy, pandas and matplotlib, are declared in its metadata.

Config settings (``pip install . --config-settings build-dir=DIR``): ``build-dir``, a CMake build
directory to build in or reuse (default: ``build-wheel/`` in the repository; a build directory the
project's scripts made, ``build/``, is reused with its own options); ``build=no``, pack what build-dir
holds without building (the test suite's check, which must not rebuild what other tests run)."""
import base64
import hashlib
import io
import os
import re
import subprocess
import sys
import sysconfig
import tarfile
import tomllib
import zipfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _project():
    with open(os.path.join(ROOT, "pyproject.toml"), "rb") as f:
        return tomllib.load(f)["project"]


def _build(config_settings):
    """Builds the package with CMake; returns BUILD/python/rotleak."""
    build = os.path.abspath((config_settings or {}).get("build-dir") or os.path.join(ROOT, "build-wheel"))
    if not os.path.exists(os.path.join(build, "CMakeCache.txt")):
        subprocess.run(["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release", "-DROTLEAK_PYTHON_MODULE=ON",
                        "-DROTLEAK_TESTS=OFF", "-DROTLEAK_BENCH=OFF", "-DPython3_EXECUTABLE=" + sys.executable],
                       check=True, stdout=sys.stderr)
    if (config_settings or {}).get("build") != "no":
        subprocess.run(["cmake", "--build", build, "--target", "rotleak_python", "-j", str(os.cpu_count() or 1)],
                       check=True, stdout=sys.stderr)
    package = os.path.join(build, "python", "rotleak")
    if not any(name.startswith("_rotleak") for name in os.listdir(package)):
        raise RuntimeError("%s: no _rotleak module was built (is pybind11 installed? Debian: pybind11-dev)" % build)
    return package


def pep440(version):
    """rotleak's version (git describe: 0.1.0, 0.1.0-3-g1234abc, 0.1.0+g1234abc, ...-dirty) as PEP 440."""
    m = re.fullmatch(r"(\d+(?:\.\d+)*)(?:-(\d+)-g([0-9a-f]+))?(?:\+g([0-9a-f]+))?(-dirty)?", version)
    if not m:
        raise RuntimeError("version %r: not one rotleak's build writes" % version)
    base, post, post_hash, plain_hash, dirty = m.groups()
    local = ["g" + h for h in (post_hash, plain_hash) if h] + (["dirty"] if dirty else [])
    return base + (".post" + post if post else "") + ("+" + ".".join(local) if local else "")


def _version(package):
    with open(os.path.join(package, "_version.py")) as f:
        m = re.search(r"__version__\s*=\s*[\"']([^\"']+)[\"']", f.read())
    if not m:
        raise RuntimeError("%s/_version.py holds no __version__" % package)
    return pep440(m.group(1))


def _metadata(version):
    p = _project()
    lines = ["Metadata-Version: 2.1", "Name: " + p["name"], "Version: " + version, "Summary: " + p["description"],
             "License: " + p["license"]["text"], "Requires-Python: " + p["requires-python"]]
    lines += ["Requires-Dist: " + d for d in p["dependencies"]]
    return "\n".join(lines) + "\n"


def _tag():
    py = "cp%d%d" % sys.version_info[:2]
    return "%s-%s-%s" % (py, py, re.sub(r"[-.]", "_", sysconfig.get_platform()))


def _hash(data):
    return "sha256=" + base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()


def build_wheel(wheel_directory, config_settings=None, metadata_directory=None):
    """PEP 517: builds the package and writes rotleak-VERSION-TAG.whl into wheel_directory."""
    package = _build(config_settings)
    version, tag = _version(package), _tag()
    info = "rotleak-%s.dist-info" % version
    files = {}
    for d, dirs, names in os.walk(package):
        dirs[:] = sorted(x for x in dirs if x != "__pycache__")
        for name in sorted(names):
            if name.endswith((".py", ".so")) and not name.endswith(".py.in"):
                path = os.path.join(d, name)
                with open(path, "rb") as f:
                    files["rotleak/" + os.path.relpath(path, package).replace(os.sep, "/")] = f.read()
    files[info + "/METADATA"] = _metadata(version).encode()
    files[info + "/WHEEL"] = ("Wheel-Version: 1.0\nGenerator: rotleak_build\nRoot-Is-Purelib: false\nTag: %s\n"
                              % tag).encode()
    record = ["%s,%s,%d" % (name, _hash(data), len(data)) for name, data in files.items()]
    files[info + "/RECORD"] = ("\n".join(record + [info + "/RECORD,,"]) + "\n").encode()
    wheel = "rotleak-%s-%s.whl" % (version, tag)
    tmp = os.path.join(wheel_directory, "." + wheel + ".tmp")
    with zipfile.ZipFile(tmp, "w", zipfile.ZIP_DEFLATED) as z:
        for name, data in files.items():
            info_ = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
            info_.external_attr = (0o755 if name.endswith(".so") else 0o644) << 16
            z.writestr(info_, data, zipfile.ZIP_DEFLATED)
    os.replace(tmp, os.path.join(wheel_directory, wheel))
    return wheel


def build_sdist(sdist_directory, config_settings=None):
    """PEP 517: the tracked files (git ls-files) as rotleak-VERSION.tar.gz, VERSION the project's."""
    with open(os.path.join(ROOT, "CMakeLists.txt")) as f:
        version = re.search(r"project\(rotleak VERSION ([0-9.]+)", f.read()).group(1)
    names = subprocess.run(["git", "-C", ROOT, "ls-files"], check=True, capture_output=True, text=True).stdout.split()
    base = "rotleak-" + version
    sdist = base + ".tar.gz"
    tmp = os.path.join(sdist_directory, "." + sdist + ".tmp")
    with tarfile.open(tmp, "w:gz") as t:
        for name in names:
            t.add(os.path.join(ROOT, name), arcname=base + "/" + name, recursive=False)
        info = _metadata(version).encode()
        member = tarfile.TarInfo(base + "/PKG-INFO")
        member.size = len(info)
        t.addfile(member, io.BytesIO(info))
    os.replace(tmp, os.path.join(sdist_directory, sdist))
    return sdist


def get_requires_for_build_wheel(config_settings=None):
    """PEP 517: nothing beyond the standard library (CMake and the compilers come from Debian)."""
    return []


def get_requires_for_build_sdist(config_settings=None):
    return []
