"""The unit store of the paper-unit runner: its SQLite tables, the run identity that keys them,
and the writes and reads of one unit.

A run is keyed by :func:`run_id` (the scenario module's source closure, the configuration, the
library versions and the codec's schema, hashed); each finished unit is one row of
``unit_results`` (the codec's compressed JSON, never pickle), committed in its own transaction
(:func:`register_run` records the run once). A store whose table has another layout (an older
gyrobench) is refused in one line before anything is written. The scheduling that fills it is
:mod:`gyrobench.scenarios.runner.units`; the connection (WAL, ``synchronous=FULL``) is the bench's
:func:`gyrobench.scenarios.runner.store.connect_db`.
"""

from __future__ import annotations

import hashlib
import json
import os
import sqlite3
import time
import types
from collections.abc import Sequence
from pathlib import Path
from typing import Any

__all__ = ["DEFAULT_DB", "default_db", "register_run", "run_id", "run_ids"]

#: default resume store (in the current directory) when no db is given
DEFAULT_DB = "gyrobench-units.sqlite"

_SCHEMA = """
CREATE TABLE IF NOT EXISTS unit_runs (
    run_id TEXT PRIMARY KEY,
    scenario TEXT NOT NULL,
    config TEXT NOT NULL,
    identity TEXT NOT NULL,
    created REAL NOT NULL
);
CREATE TABLE IF NOT EXISTS unit_results (
    run_id TEXT NOT NULL REFERENCES unit_runs(run_id),
    seed INTEGER NOT NULL,
    result BLOB NOT NULL,
    elapsed_s REAL NOT NULL,
    finished REAL NOT NULL,
    full INTEGER NOT NULL,
    PRIMARY KEY (run_id, seed)
);
"""

#: the columns of a unit store this gyrobench writes; a store without them is an older format
_COLUMNS = ("run_id", "seed", "result", "elapsed_s", "finished", "full")


def run_id(module: types.ModuleType, config: Any) -> tuple[str, str]:
    """(16-hex run id, its JSON identity) of ``module`` with ``config``.

    Parameters
    ----------
    module : module
        The paper scenario.
    config : object
        Its Config.

    Returns
    -------
    tuple of (str, str)
        (16-hex run id, the JSON identity it hashes).
    """
    from gyrobench.scenarios.bench.identity import scenario_identity
    from gyrobench.scenarios.runner.codec import SCHEMA

    ident = dict(scenario_identity(module, config), store_format=SCHEMA)  # old pickled stores never match
    text = json.dumps(ident, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16], text


def run_ids(module: types.ModuleType, configs: Sequence[Any]) -> list[tuple[str, str]]:
    """The :func:`run_id` of ``module`` with each of ``configs``, its source closure hashed once.

    Parameters
    ----------
    module : module
        A paper scenario.
    configs : sequence of the module's Config
        The configurations.

    Returns
    -------
    list of (str, str)
        Each config's (16-hex run id, JSON identity), equal to :func:`run_id`'s.
    """
    from gyrobench.scenarios.bench.identity import canonical, scenario_identity
    from gyrobench.scenarios.runner.codec import SCHEMA

    if not configs:
        return []
    base = dict(scenario_identity(module, configs[0]), store_format=SCHEMA)
    out = []
    for c in configs:
        text = json.dumps(dict(base, config=canonical(c)), sort_keys=True)
        out.append((hashlib.sha256(text.encode()).hexdigest()[:16], text))
    return out



def _decode(blob: bytes, seed: int, db: str | os.PathLike) -> Any:
    """A stored unit result, decoded without running code (a one-line ValueError naming the db
    and the seed if the row is not a result the codec wrote)."""
    from gyrobench.scenarios.runner import codec

    try:
        return codec.loads(blob)
    except codec.CodecError as exc:
        raise ValueError(f"db {str(db)!r}: stored unit (seed {seed}) refused: {exc}") from None



def _check_layout(db: str | os.PathLike) -> None:
    """Refuse, in one line and before anything is written, an existing unit store whose table has
    another layout than :data:`_COLUMNS` (a store of an older gyrobench)."""
    p = Path(db)
    if not p.is_file() or p.stat().st_size == 0:
        return
    try:
        conn = sqlite3.connect(f"{p.resolve().as_uri()}?mode=ro", uri=True)
    except sqlite3.Error:
        return  # connect_db names what is wrong with the file
    try:
        have = tuple(r[1] for r in conn.execute("PRAGMA table_info(unit_results)"))
    except sqlite3.DatabaseError:
        return
    finally:
        conn.close()
    if have and have != _COLUMNS:
        raise ValueError(
            f"db {str(db)!r} is a unit store of an older gyrobench (columns {', '.join(have)}); "
            "delete it (its units are recomputed) or give another --db"
        )


def _open_store(
    db: str | os.PathLike, rid: str, name: str, config: Any, identity: str
) -> sqlite3.Connection:
    from gyrobench.scenarios.runner.store import connect_db

    _check_layout(db)
    conn = connect_db(db, _SCHEMA)  # WAL, synchronous=FULL, checks the folder exists
    try:
        register_run(conn, rid, name, config, identity)
    except BaseException:
        conn.close()
        raise
    return conn


def register_run(conn: sqlite3.Connection, rid: str, name: str, config: Any, identity: str) -> None:
    """Record a run in an open unit store, once (a second call for the same run id does nothing).

    Parameters
    ----------
    conn : sqlite3.Connection
        The unit store (:func:`gyrobench.scenarios.runner.store.connect_db`).
    rid : str
        The run id (:func:`run_id`).
    name : str
        The scenario's name.
    config : Any
        The run's configuration (stored as its repr).
    identity : str
        The run's JSON identity (:func:`run_id`).
    """
    conn.execute("BEGIN IMMEDIATE")
    conn.execute(
        "INSERT OR IGNORE INTO unit_runs VALUES (?, ?, ?, ?, ?)",
        (rid, name, repr(config), identity, time.time()),
    )
    conn.execute("COMMIT")


def _store(conn: sqlite3.Connection, rid: str, seed: int, blob: bytes, elapsed: float, full: bool) -> bytes:
    """Commit one unit; return the stored blob (another process may have stored it first; a whole
    result replaces a slim one, never the other way)."""
    conn.execute("BEGIN IMMEDIATE")
    try:
        conn.execute(
            "INSERT INTO unit_results VALUES (?, ?, ?, ?, ?, ?) ON CONFLICT (run_id, seed) DO UPDATE SET "
            "result = excluded.result, elapsed_s = excluded.elapsed_s, finished = excluded.finished, "
            "full = excluded.full WHERE excluded.full > unit_results.full",
            (rid, seed, blob, elapsed, time.time(), int(full)),
        )
        (stored,) = conn.execute(
            "SELECT result FROM unit_results WHERE run_id = ? AND seed = ?", (rid, seed)
        ).fetchone()
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    conn.execute("COMMIT")
    return bytes(stored)



def default_db(out_dir: str | os.PathLike) -> Path:
    """The resume store beside a report folder: ``<out_dir>.units.sqlite``.

    Beside, not inside: the report folder is replaced as a whole by each new report
    (:func:`gyrobench.scenarios.reports.outputs.write_report_as_a_set`), the store must survive it.

    Parameters
    ----------
    out_dir : path-like
        The report folder.

    Returns
    -------
    Path
        ``<out_dir>.units.sqlite``.
    """
    out = Path(out_dir)
    return out.with_name(out.name + ".units.sqlite")
