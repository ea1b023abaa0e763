"""The results databases' files: the bench's schema, opening a database (WAL journal,
``synchronous=FULL``, created with its application id), the key beside it, and the refusal of a
file that is not a database gyrobench made.

:func:`connect_db` opens any results database (the bench's schema, :data:`SCHEMA`, or the units
runner's, :mod:`gyrobench.scenarios.runner.unit_store`); :func:`db_key` creates and reads the
32-byte key (``<db>.key``, mode 0600) the seed checksums are keyed with. The bench's reads and
writes of the rows are :mod:`gyrobench.scenarios.runner.store`.
"""

from __future__ import annotations

import os
import sqlite3
from pathlib import Path

from gyrobench.base.safety import SQLITE_APPLICATION_ID

__all__ = [
    "DEFAULT_DB",
    "KEY_BYTES",
    "SCHEMA",
    "KeyedConnection",
    "check_database",
    "check_output_file",
    "connect_db",
    "database_tables",
    "db_key",
    "key_path",
]

#: default campaign database (in the current directory)
DEFAULT_DB = "gyrobench-bench.sqlite"

SCHEMA = """
CREATE TABLE IF NOT EXISTS campaigns (
    campaign_id TEXT PRIMARY KEY,
    scenario TEXT NOT NULL,
    compensator TEXT NOT NULL,
    config TEXT NOT NULL,
    identity TEXT NOT NULL,
    created REAL NOT NULL
);
CREATE TABLE IF NOT EXISTS seed_scores (
    campaign_id TEXT NOT NULL REFERENCES campaigns(campaign_id),
    seed INTEGER NOT NULL,
    scores TEXT NOT NULL,
    elapsed_s REAL NOT NULL,
    finished REAL NOT NULL,
    session_id INTEGER NOT NULL REFERENCES sessions(session_id),
    PRIMARY KEY (campaign_id, seed)
);
CREATE TABLE IF NOT EXISTS seed_failures (
    campaign_id TEXT NOT NULL REFERENCES campaigns(campaign_id),
    seed INTEGER NOT NULL,
    reason TEXT NOT NULL,
    PRIMARY KEY (campaign_id, seed)
);
CREATE TABLE IF NOT EXISTS seed_checksums (
    campaign_id TEXT NOT NULL REFERENCES campaigns(campaign_id),
    seed INTEGER NOT NULL,
    sha256 TEXT NOT NULL,
    PRIMARY KEY (campaign_id, seed)
);
CREATE TABLE IF NOT EXISTS campaign_reads (
    campaign_id TEXT PRIMARY KEY,
    static_id TEXT NOT NULL,
    generation INTEGER NOT NULL,
    names TEXT NOT NULL,
    fingerprint TEXT NOT NULL
);
CREATE TABLE IF NOT EXISTS sessions (
    session_id INTEGER PRIMARY KEY AUTOINCREMENT,
    campaign_id TEXT NOT NULL REFERENCES campaigns(campaign_id),
    started REAL NOT NULL,
    n_requested INTEGER NOT NULL,
    n_reused INTEGER NOT NULL,
    pid INTEGER NOT NULL
);
"""


def connect_db(path: str | os.PathLike, schema: str | None = None) -> sqlite3.Connection:
    """Open (or create) a results database with its schema applied.

    Open (or create) a results database: WAL, synchronous=FULL, ``schema`` (default the
    bench's) applied; bad paths and unwritable folders are one-line ValueErrors.

    Shared by the bench and :mod:`gyrobench.scenarios.runner.units` (each with its own schema).

    Parameters
    ----------
    path : path-like
        The database file.
    schema : str or None
        The SQL schema to apply (None: the bench's :data:`SCHEMA`).

    Returns
    -------
    sqlite3.Connection
        In WAL mode with synchronous=FULL.
    """
    keyed = schema is None
    schema = SCHEMA if schema is None else schema
    p = check_output_file(path, what="db")
    check_database(p, what="db")  # a foreign SQLite file is refused before anything is written to it
    if not p.exists():
        _create_database(p, schema)  # whole, marked and with its schema: a kill never leaves an empty file
    try:
        # explicit BEGIN/COMMIT; the connection carries the database's checksum key
        conn = sqlite3.connect(str(p), timeout=60.0, isolation_level=None, factory=KeyedConnection)
    except sqlite3.Error as exc:
        raise ValueError(f"db {str(p)!r} cannot be opened: {exc}") from None
    try:
        conn.execute("PRAGMA busy_timeout = 60000")
        mode = conn.execute("PRAGMA journal_mode = WAL").fetchone()[0]
        if str(mode).lower() != "wal":
            raise ValueError(f"db {str(p)!r}: cannot switch to WAL journal mode (got {mode!r})")
        conn.execute("PRAGMA synchronous = FULL")
        if not conn.execute("PRAGMA application_id").fetchone()[0]:  # the mark check_database recognises
            conn.execute(f"PRAGMA application_id = {int(SQLITE_APPLICATION_ID)}")
        conn.executescript(schema)
    except sqlite3.OperationalError as exc:  # an unwritable folder or file, a read-only file system
        conn.close()
        writable = os.access(p.parent, os.W_OK) and (not p.exists() or os.access(p, os.W_OK))
        why = "" if writable else " (no write permission)"
        raise ValueError(
            f"db {str(p)!r} cannot be opened for writing{why}: {exc}; "
            "give --db in a writable folder"
        ) from None
    except sqlite3.DatabaseError as exc:
        conn.close()
        raise ValueError(f"db {str(p)!r} is not a usable SQLite database: {exc}") from None
    if keyed:
        try:
            conn.key = db_key(p)
        except ValueError:
            conn.close()
            raise
    return conn


def _create_database(p: Path, schema: str) -> None:
    """Create the database ``p`` atomically: its mark (``application_id``) and ``schema`` are written to a
    temporary file beside it, which is renamed to ``p`` when complete."""
    from gyrobench.base.atomic import atomic_path

    try:
        with atomic_path(p) as tmp:
            conn = sqlite3.connect(str(tmp), isolation_level=None)
            try:
                conn.execute(f"PRAGMA application_id = {int(SQLITE_APPLICATION_ID)}")
                conn.executescript(schema)
            finally:
                conn.close()
    except (sqlite3.Error, OSError) as exc:
        raise ValueError(f"db {str(p)!r} cannot be created: {exc}; give --db in a writable folder") from None


class KeyedConnection(sqlite3.Connection):
    """A results database's connection with its checksum key (:func:`db_key`; ``b""``: unkeyed)."""

    key: bytes = b""


#: bytes of a database's checksum key
KEY_BYTES = 32


def key_path(db: str | os.PathLike) -> Path:
    """The key file of database ``db``: ``<db>.key`` beside it.

    Parameters
    ----------
    db : path-like
        The database file.

    Returns
    -------
    Path
        ``<db>.key``.
    """
    return Path(f"{os.fspath(db)}.key")


def db_key(db: str | os.PathLike) -> bytes:
    """The checksum key of a database, created if it has none.

    The checksum key of database ``db``, created (32 random bytes, mode 0600, never
    overwritten) if it has none.

    Parameters
    ----------
    db : path-like
        The database file.

    Returns
    -------
    bytes
        The 32-byte key.

    Raises
    ------
    ValueError
        If the key file cannot be read or created, or does not hold 32 bytes.
    """
    path = key_path(db)
    try:
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    except FileExistsError:
        pass
    except OSError as exc:
        raise ValueError(f"db key {str(path)!r} cannot be created: {exc.strerror}") from None
    else:
        try:
            os.write(fd, os.urandom(KEY_BYTES))
            os.fsync(fd)
        finally:
            os.close(fd)
    try:
        key = path.read_bytes()
    except OSError as exc:
        raise ValueError(f"db key {str(path)!r} cannot be read: {exc.strerror}") from None
    if len(key) != KEY_BYTES:
        raise ValueError(
            f"db key {str(path)!r} must hold {KEY_BYTES} bytes; got {len(key)} (remove it and the database "
            "to start again: without its key no stored seed can be verified)"
        )
    return key


def database_tables() -> tuple[str, ...]:
    """The tables of gyrobench's databases: the bench's (:data:`SCHEMA`) and the units runner's.

    Returns
    -------
    tuple of str
        The table names.
    """
    import re

    from gyrobench.scenarios.runner.unit_store import _SCHEMA

    return tuple(re.findall(r"CREATE TABLE IF NOT EXISTS (\w+)", SCHEMA + _SCHEMA))


def check_database(path: str | os.PathLike, *, what: str, force: bool = False) -> Path:
    """Refuse an existing file that is not a database gyrobench made, before anything is written.

    Refuse, before anything is written, an existing ``path`` that is not a database gyrobench made
    (:func:`gyrobench.base.safety.check_database`; ``force`` lets an empty file be used).

    Parameters
    ----------
    path : path-like
        The database file.
    what : str
        How the user named it (a flag), for the message.
    force : bool
        Let an empty file be used.

    Returns
    -------
    Path
        ``path`` as a Path.
    """
    from gyrobench.base import safety

    return safety.check_database(path, what, database_tables(), force=force)


def check_output_file(path: str | os.PathLike, *, what: str) -> Path:
    """Check that a path can be written as a file, without creating folders.

    ``path`` as a Path if it can be written as a file: not a folder, its folder exists
    and accepts new files (:func:`gyrobench.scenarios.reports.outputs.check_output`).

    Missing folders are never created: a typo (or ``/nonexist/dir/b.json`` run as
    root) must not scatter folders over the file system.

    Parameters
    ----------
    path : path-like
        The output file.
    what : str
        How the user named it (a flag), for the message.

    Returns
    -------
    Path
        ``path`` as a Path.
    """
    from gyrobench.scenarios.reports.outputs import check_output

    return check_output(path, what=what, kind="file", create_parents=False)
