#!/usr/bin/env python3
"""The container image's runtime stage provides what the binaries link
(issue 31), checked without building the image: every shared library a
binary names (ELF NEEDED) is resolved to its file (ldd) and to the Debian
package that ships it (dpkg -S); that package must be one the runtime
stage of deploy/Dockerfile installs, or a dependency of one (Depends and
Pre-Depends, recursively, through the installed packages' metadata, so no
apt lists are needed).

    runtime_libs.py DOCKERFILE BINARY...        (ctest: deploy_runtime_libs)

Exit 0 when every library is provided; 1 listing the ones that are not,
each with its package; 2 when the check itself cannot run.
"""
import os
import re
import subprocess
import sys


def runtime_packages(dockerfile):
    """The packages of the last stage's `apt-get install` lines."""
    text = open(dockerfile, encoding="utf-8").read().replace("\\\n", " ")
    stages = re.split(r"^FROM\s", text, flags=re.M)
    packages = []
    for line in stages[-1].splitlines():
        m = re.search(r"apt-get install ([^&;]*)", line)
        if m:
            packages += [w for w in m.group(1).split() if not w.startswith("-")]
    return packages


def installed():
    """{package: (depends, provides)} of every installed package."""
    out = subprocess.run(
        ["dpkg-query", "-W", "-f", "${Package}\t${Status}\t${Pre-Depends}, ${Depends}\t${Provides}\n"],
        capture_output=True, text=True, check=True).stdout
    db = {}
    for line in out.splitlines():
        name, status, depends, provides = (line.split("\t") + ["", "", ""])[:4]
        if "installed" not in status.split():
            continue
        db[name] = (depends, provides)
    return db


def closure(roots, db):
    """The roots and everything they depend on, through the installed
    packages (alternatives: each one installed; virtual names: their
    installed providers)."""
    providers = {}
    for name, (_, provides) in db.items():
        for p in provides.split(","):
            p = p.split("(")[0].strip()
            if p:
                providers.setdefault(p, set()).add(name)
    seen, todo, unknown = set(), list(roots), []
    while todo:
        name = todo.pop().split(":")[0]
        if name in seen:
            continue
        seen.add(name)
        if name not in db:
            if name in providers:
                todo += providers[name]
            elif name in roots:
                unknown.append(name)
            continue
        for clause in db[name][0].split(","):
            for alt in clause.split("|"):
                dep = alt.split("(")[0].strip().split(":")[0]
                if dep and (dep in db or dep in providers):
                    todo.append(dep)
    return seen, unknown


def needed_libraries(binary):
    """[(soname, path)] of the binary's NEEDED entries, paths from ldd."""
    dynamic = subprocess.run(["readelf", "-d", binary], capture_output=True, text=True,
                             check=True).stdout
    needed = re.findall(r"\(NEEDED\)\s+Shared library: \[([^\]]+)\]", dynamic)
    ldd = subprocess.run(["ldd", binary], capture_output=True, text=True, check=True).stdout
    paths = dict(re.findall(r"^\s*(\S+) => (\S+)", ldd, flags=re.M))
    return [(so, paths.get(so)) for so in needed]


def candidates_of(path):
    """The spellings dpkg may know a library by (merged /usr, links)."""
    candidates = [path, os.path.realpath(path)]
    for c in list(candidates):
        if c.startswith("/usr/lib/"):
            candidates.append(c[len("/usr"):])
        elif c.startswith("/lib/"):
            candidates.append("/usr" + c)
    return candidates


def packages_of(paths):
    """{path: package} for the paths dpkg knows, in one dpkg -S call (one
    call per path took most of this test's 27 s)."""
    spellings = sorted({c for p in paths for c in candidates_of(p)})
    # dpkg -S exits 1 when any spelling is unknown; the known ones are still
    # printed, one "package[:arch][, package...]: path" line each.
    out = subprocess.run(["dpkg", "-S"] + spellings, capture_output=True, text=True).stdout
    owner = {}
    for line in out.splitlines():
        packages, sep, path = line.partition(": ")
        if sep and path.strip() in spellings:
            owner[path.strip()] = packages.split(",")[0].split(":")[0].strip()
    found = {}
    for p in paths:
        for c in candidates_of(p):
            if c in owner:
                found[p] = owner[c]
                break
    return found


def main():
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    dockerfile, binaries = sys.argv[1], sys.argv[2:]
    roots = runtime_packages(dockerfile)
    if not roots:
        print(f"{dockerfile}: no apt-get install in the runtime stage", file=sys.stderr)
        return 2
    db = installed()
    provided, unknown = closure(roots, db)
    if unknown:
        # Not installed here, so their dependencies cannot be followed;
        # what they ship is still counted by name.
        print("not installed here (dependencies not followed): " + " ".join(unknown))
    missing = []
    libraries = {binary: needed_libraries(binary) for binary in binaries}
    owner = packages_of([path for libs in libraries.values() for _, path in libs if path])
    for binary, libs in libraries.items():
        for soname, path in libs:
            if path is None:
                missing.append(f"{os.path.basename(binary)}: {soname} is not found by ldd here")
                continue
            package = owner.get(path)
            if package is None:
                missing.append(f"{os.path.basename(binary)}: {soname} ({path}) is in no package")
            elif package not in provided:
                missing.append(f"{os.path.basename(binary)}: {soname} comes from package "
                               f"{package}, which the runtime stage does not install")
        print(f"{os.path.basename(binary)}: {len(libs)} libraries checked")
    if missing:
        print("\n".join(missing))
        print(f"add the packages above to the runtime stage of {dockerfile}")
        return 1
    print(f"every library is provided by the runtime stage's {len(roots)} packages "
          f"({len(provided)} with their dependencies)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
