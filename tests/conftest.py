"""Fixtures shared by every test package."""

import hashlib
import os
import sqlite3
import stat
import zlib
from pathlib import Path

import numpy as np
import pytest


@pytest.fixture
def rng(request) -> np.random.Generator:
    """The same stream on every run, a different one for every test."""
    key = zlib.crc32(request.node.nodeid.encode())
    return np.random.default_rng([20261121, key])

# Property tests draw the same examples on every run (the equivalent of a fixed seed), so a
# CI result never depends on which examples Hypothesis happened to try.
from hypothesis import settings as _hypothesis_settings  # noqa: E402

_hypothesis_settings.register_profile("gyrobench", derandomize=True, database=None)
_hypothesis_settings.load_profile("gyrobench")


# ----------------------------------------------------------------------------- the user's files
class UserFiles:
    """User files planted where a command reads or could write, and the check that none changed.

    :meth:`plant` writes a file (bytes, or a foreign file of a format: ``"hdf5"``, ``"sqlite"``),
    :meth:`keep` records a file the test made (an input), :meth:`around` plants the neighbours
    of an output. :meth:`watch` does both for every command, from the inputs and outputs it
    names to the output rule. :meth:`verify` (run when the test ends) fails the test if any
    recorded file is gone, is no longer a regular file, or has other bytes.
    """

    def __init__(self, root: Path) -> None:
        self.root = root
        self._kept: dict[Path, tuple[str, int]] = {}
        #: what the running command read or may not replace, verified when it ends (:meth:`command`)
        self._command: dict[Path, tuple[str, int]] = {}

    @staticmethod
    def _digest(p: Path) -> tuple[str, int]:
        st = os.stat(p)
        return hashlib.sha256(p.read_bytes()).hexdigest(), st.st_ino

    def keep(self, *paths: "str | os.PathLike") -> None:
        """Record existing files: each must still hold its bytes when the test ends."""
        for p in map(Path, paths):
            self._kept[p] = self._digest(p)

    def plant(self, path: "str | os.PathLike", data: "bytes | str" = b"", *, kind: str = "bytes") -> Path:
        """Write a user file at ``path`` (its folders made) and record it; returns the path."""
        p = Path(path)
        if not p.is_absolute():
            p = self.root / p
        p.parent.mkdir(parents=True, exist_ok=True)
        if kind == "hdf5":  # a foreign HDF5 file: no gyrobench marker
            import h5py

            with h5py.File(p, "w") as h5:
                h5["data"] = list(range(8))
                h5.attrs["owner"] = "user"
        elif kind == "sqlite":  # a foreign SQLite database
            conn = sqlite3.connect(p)
            conn.execute("CREATE TABLE notes (line TEXT)")
            conn.execute("INSERT INTO notes VALUES ('mine')")
            conn.commit()
            conn.close()
        else:
            p.write_bytes(data.encode() if isinstance(data, str) else (data or f"user file {p.name}\n".encode()))
        self.keep(p)
        return p

    def neighbours(self, out: Path) -> list[Path]:
        """The user files planted beside output ``out``, by names no command writes and no listing of its
        suffix finds (``NAME.user``, ``NAME.bak``, ``STEM_notes.txt``)."""
        return [out.with_name(out.name + ".user"), out.with_name(out.name + ".bak"),
                out.with_name(f"{out.stem}_notes.txt")]

    def around(self, *outputs: "str | os.PathLike") -> list[Path]:
        """Plant user files beside each output (:meth:`neighbours`) inside the test's folder, never at it."""
        planted = []
        for out in map(Path, outputs):
            for n in self.neighbours(out):
                if self._inside(n) and not n.exists() and not n.is_symlink() and n.parent.is_dir():
                    planted.append(self.plant(n))
        return planted

    def _inside(self, p: Path) -> bool:
        return os.path.realpath(p).startswith(os.path.realpath(self.root) + os.sep)

    def planted_names(self, folder: "str | os.PathLike") -> set[str]:
        """The names of the entries of ``folder`` this fixture planted (to leave out of a listing)."""
        f = os.path.realpath(folder)
        names = {Path(p).name for p in self._kept if os.path.realpath(Path(p).parent) == f}
        if f == os.path.realpath(self.root):
            names.add("user")
        return names

    def written(self, folder: "str | os.PathLike") -> list[Path]:
        """The entries of ``folder`` (sorted) that the fixture did not plant: what the commands made."""
        skip = self.planted_names(folder)
        return sorted(p for p in Path(folder).iterdir() if p.name not in skip)

    def watch(self, check):
        """Wrap :func:`gyrobench.base.safety.check_outputs`: each command's inputs and the existing targets it
        may not replace are recorded, and user files are planted beside its outputs, before it checks them."""
        from gyrobench.base import safety

        def watching(outputs, inputs=(), *, force=False, tables=()):
            inputs = list(inputs)
            for _, p in inputs:
                if p is not None and Path(p).is_file():
                    self._command[Path(p)] = self._digest(Path(p))
            for o in outputs:
                p = Path(o.path)
                if p.is_file() and o.kind == "file" and not force and not safety.written_by_gyrobench(p):
                    self._command[p] = self._digest(p)
                if o.kind == "database" and p.is_file():
                    try:
                        safety.check_database(p, o.flag, tables)
                    except ValueError:
                        self._command[p] = self._digest(p)
            self.around(*(Path(o.path) for o in outputs))
            return check(outputs, inputs, force=force, tables=tables)

        return watching

    def command(self, build_parser):
        """Wrap the command line's ``build_parser`` so that each verb, when it ends (however it ends),
        verifies what it read or was not allowed to replace (recorded by :meth:`watch`)."""
        import functools

        def verified(func):
            @functools.wraps(func)
            def run(args):
                try:
                    return func(args)
                finally:
                    kept, self._command = self._command, {}
                    self.verify(kept)

            return run

        def build():
            parser = build_parser()
            parse = parser.parse_args

            def parse_args(*a, **kw):
                args = parse(*a, **kw)
                args.func = verified(args.func)
                return args

            parser.parse_args = parse_args
            return parser

        return build

    def verify(self, kept: "dict[Path, tuple[str, int]] | None" = None) -> None:
        """Fail if any recorded file was removed, replaced by another kind of entry or changed."""
        changed = []
        for p, (digest, _) in (self._kept if kept is None else kept).items():
            try:
                st = os.stat(p)
            except OSError:
                changed.append(f"{p} is gone")
                continue
            if not stat.S_ISREG(st.st_mode):
                changed.append(f"{p} is no longer a regular file")
            elif self._digest(p)[0] != digest:
                changed.append(f"{p} has other bytes")
        if changed:
            pytest.fail("a user's file changed: " + "; ".join(changed), pytrace=False)


@pytest.fixture
def user_files(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    """:class:`UserFiles`: a foreign HDF5, SQLite, JSON, YAML, CSV and PNG file and a folder of notes
    planted in ``tmp_path/user``; every command's inputs recorded, and user files planted beside its
    outputs, when it checks them (:meth:`UserFiles.watch`); the test fails if any recorded file changes."""
    from gyrobench.base import safety
    from gyrobench.scenarios.cli import main as cli

    files = UserFiles(tmp_path)
    monkeypatch.setattr(safety, "check_outputs", files.watch(safety.check_outputs))
    monkeypatch.setattr(cli, "build_parser", files.command(cli.build_parser))
    user = tmp_path / "user"
    files.plant(user / "foreign.h5", kind="hdf5")
    files.plant(user / "foreign.sqlite", kind="sqlite")
    files.plant(user / "notes.json", '{"format": "mine", "notes": [1, 2]}\n')
    files.plant(user / "notes.yaml", "notes: mine\n")
    files.plant(user / "real.csv", "time [s],gyro [deg/s]\n0,0.1\n0.01,0.2\n")
    files.plant(user / "plot.png", b"\x89PNG\r\n\x1a\n not gyrobench's")
    files.plant(user / "folder" / "keep.txt", "mine\n")
    yield files
    files.verify()
    files.verify(files._command)  # a library call that checked its outputs outside a command


def _slow_tier_ids() -> tuple[frozenset[str], tuple[str, ...]]:
    """The node ids tests/data/slow_tier.txt moves to the slow tier: exact ids, and the prefixes of
    parametrised ids whose parameters ``--durations`` printed only in part."""
    exact, prefixes = set(), []
    for line in (Path(__file__).parent / "data" / "slow_tier.txt").read_text(encoding="utf-8").splitlines():
        nid = line.split("  #", 1)[0].strip()
        if not nid or nid.startswith("#"):
            continue
        if "[" in nid and not nid.endswith("]"):
            prefixes.append(nid)
        else:
            exact.add(nid)
    return frozenset(exact), tuple(prefixes)


@pytest.hookimpl(tryfirst=True)  # before -m 'not slow' deselects by marker
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Mark ``slow`` every test tests/data/slow_tier.txt lists (the default tier's heaviest end)."""
    exact, prefixes = _slow_tier_ids()
    for item in items:
        if item.nodeid in exact or item.nodeid.startswith(prefixes):
            item.add_marker(pytest.mark.slow)
