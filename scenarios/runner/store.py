"""The results store: an SQLite file written only by the calling process, WAL journal,
``synchronous=FULL``, one transaction per finished seed.

:func:`connect_db` opens any results database (the bench's schema, :data:`SCHEMA`, or the
units runner's, :mod:`gyrobench.scenarios.runner.units`). :func:`start_session` and
:func:`record_seed` are the bench's reads and writes: a campaign's finished seeds are read
back on a rerun, so a campaign killed at any moment (even SIGKILL) resumes where it stopped.

Every stored seed carries a checksum (:func:`seed_checksum`: HMAC-SHA256, keyed with the
database's own key, of the campaign id, the seed, the scores' text and the failure reason) in
``seed_checksums``, written in the same transaction. The key is 32 random bytes in a file
beside the database (``<db>.key``, mode 0600, created with it: :func:`db_key`). A resume
verifies it: a row edited in the file (a score set to ``"nan"``), a corrupted one, one written
before checksums existed, or a forged one whose checksum was recomputed without the key, is
deleted with a warning and its seed recomputed, never served and never silently dropped from
the summary. Whoever can read the key file (the same user, the compensator's own process) can
still forge a row: the checksum guards against accidents and against edits by anyone without
the key, not against the user's own code.

What a campaign's compensator read (:mod:`~gyrobench.scenarios.bench.sandbox`: modules, files,
environment variables) is kept per campaign in ``campaign_reads``, with its fingerprints;
:func:`campaign_generation` picks, among the stored campaigns of one static identity, the one
whose reads are unchanged, or starts a new one.
"""

from __future__ import annotations

import hashlib
import json
import math
import os
import sqlite3
import time
import warnings
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from gyrobench.base.safety import SQLITE_APPLICATION_ID
from gyrobench.scenarios.cli import exits

__all__ = [
    "DEFAULT_DB",
    "KEY_BYTES",
    "SCHEMA",
    "KeyedConnection",
    "campaign_generation",
    "db_key",
    "key_path",
    "record_reads",
    "Session",
    "check_database",
    "check_output_file",
    "database_tables",
    "connect_db",
    "dumps_scores",
    "loads_scores",
    "record_seed",
    "seed_checksum",
    "start_session",
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

    from gyrobench.scenarios.runner import units

    return tuple(re.findall(r"CREATE TABLE IF NOT EXISTS (\w+)", SCHEMA + units._SCHEMA))


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


def dumps_scores(scores: Mapping[str, float]) -> str:
    """One seed's scores as the JSON text the store keeps (keys sorted).

    JSON floats round-trip exactly (repr); NaN and inf are stored as strings so the text
    stays valid JSON (:func:`loads_scores` reads them back).

    Parameters
    ----------
    scores : mapping of str to float
        One seed's scores.

    Returns
    -------
    str
        JSON text, keys sorted, NaN and inf as strings.
    """
    return json.dumps(
        {k: (v if math.isfinite(v) else repr(v)) for k, v in scores.items()}, sort_keys=True
    )


def loads_scores(text: str) -> dict[str, float]:
    """The scores stored by :func:`dumps_scores`, as floats.

    Parameters
    ----------
    text : str
        JSON text written by :func:`dumps_scores`.

    Returns
    -------
    dict of str to float
        The scores.
    """
    return {k: float(v) for k, v in json.loads(text).items()}


def seed_checksum(campaign_id: str, seed: int, scores_text: str, failure: str | None, key: bytes = b"") -> str:
    """The checksum (hex) of one stored seed.

    Checksum (hex) of one stored seed: campaign id, seed, scores text and failure reason;
    HMAC-SHA256 with ``key`` (the database's, :func:`db_key`), SHA-256 without one.

    Parameters
    ----------
    campaign_id : str
        The campaign.
    seed : int
        The seed.
    scores_text : str
        Its scores as stored (:func:`dumps_scores`).
    failure : str or None
        Its failure reason.
    key : bytes
        The database's key (:func:`db_key`); empty: plain SHA-256.

    Returns
    -------
    str
        Hexadecimal HMAC-SHA256 (SHA-256 without a key).
    """
    import hmac

    doc = json.dumps([campaign_id, int(seed), scores_text, failure], separators=(",", ":")).encode("utf-8")
    if key:
        return hmac.new(key, doc, hashlib.sha256).hexdigest()
    return hashlib.sha256(doc).hexdigest()


def _verified(conn: sqlite3.Connection, campaign_id: str, wanted: set[int]) -> tuple[dict, dict]:
    """The stored seeds among ``wanted`` whose checksum holds (scores, failures); the others are
    deleted (inside the caller's transaction) with one warning naming them, so they are recomputed."""
    failures = dict(conn.execute("SELECT seed, reason FROM seed_failures WHERE campaign_id = ?", (campaign_id,)))
    sums = dict(conn.execute("SELECT seed, sha256 FROM seed_checksums WHERE campaign_id = ?", (campaign_id,)))
    done: dict[int, dict[str, float]] = {}
    bad: list[int] = []
    for seed, text in conn.execute("SELECT seed, scores FROM seed_scores WHERE campaign_id = ?", (campaign_id,)):
        if seed not in wanted:
            continue
        ok = isinstance(text, str) and sums.get(seed) == seed_checksum(
            campaign_id, seed, text, failures.get(seed), getattr(conn, "key", b"")
        )
        try:
            scores = loads_scores(text) if ok else None
        except (ValueError, TypeError, AttributeError):
            scores = None
        if scores is None:
            bad.append(seed)
        else:
            done[seed] = scores
    for seed in bad:
        for table in ("seed_scores", "seed_failures", "seed_checksums"):
            conn.execute(f"DELETE FROM {table} WHERE campaign_id = ? AND seed = ?", (campaign_id, seed))
    if bad:
        warnings.warn(
            f"campaign {campaign_id}: the stored scores of seed(s) {', '.join(map(str, sorted(bad)))} do not match "
            "their checksum (edited, forged, corrupted or stored by an older gyrobench); recomputing them",
            RuntimeWarning,
            stacklevel=3,
        )
    return done, {s: r for s, r in failures.items() if s in done}


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


@dataclass(frozen=True, slots=True, kw_only=True)
class Session:
    """One run of a campaign on a database: its session row and the seeds already stored.

    ``done`` maps each requested seed found in the database to its scores (as stored);
    ``failed`` maps those of them that failed to why.

    Parameters
    ----------
    session_id : int
        The session's row id.
    done : mapping of int to mapping of str to float
        Each requested seed already stored -> its scores.
    failed : mapping of int to str
        The stored seeds that failed -> why.
    """

    session_id: int
    done: Mapping[int, Mapping[str, float]]
    failed: Mapping[int, str]


def start_session(
    conn: sqlite3.Connection,
    campaign_id: str,
    seeds: Iterable[int],
    *,
    scenario: str,
    compensator: str,
    config: str,
    identity: str,
) -> Session:
    """Register a campaign, read back its stored seeds and open a session, in one transaction.

    Register the campaign (once), read back its stored seeds among ``seeds`` and open a
    session, in one transaction.

    Parameters
    ----------
    conn : sqlite3.Connection
        The open results database.
    campaign_id : str
        The campaign.
    seeds : iterable of int
        The seeds requested.
    scenario : str
        The scenario's name.
    compensator : str
        The compensator's ``"module:attr"`` name.
    config : str
        The configuration's JSON identity.
    identity : str
        The compensator's code identity.

    Returns
    -------
    Session
        The session and the requested seeds already stored.
    """
    seeds = tuple(seeds)
    conn.execute("BEGIN IMMEDIATE")
    try:
        conn.execute(
            "INSERT OR IGNORE INTO campaigns VALUES (?, ?, ?, ?, ?, ?)",
            (campaign_id, scenario, compensator, config, identity, time.time()),
        )
        done, failed = _verified(conn, campaign_id, set(seeds))
        cur = conn.execute(
            "INSERT INTO sessions (campaign_id, started, n_requested, n_reused, pid) "
            "VALUES (?, ?, ?, ?, ?)",
            (campaign_id, time.time(), len(seeds), len(done), os.getpid()),
        )
        session_id = int(cur.lastrowid or 0)
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    conn.execute("COMMIT")
    return Session(session_id=session_id, done=done, failed=failed)


def record_seed(
    conn: sqlite3.Connection,
    campaign_id: str,
    session_id: int,
    seed: int,
    scores: Mapping[str, float],
    elapsed: float,
    failure: str | None,
    *,
    db: str,
) -> tuple[dict[str, float], str | None]:
    """Commit one finished seed and return it as a resume reads it back.

    Commit one finished seed; return its scores exactly as a resume reads them back, and
    why it failed (None if it did not).

    Another process running the same campaign on the same file may have stored the seed
    meanwhile: scores are deterministic, so it must be the same, else
    :class:`~gyrobench.scenarios.cli.exits.InternalError` (``db`` names the file).

    Parameters
    ----------
    conn : sqlite3.Connection
        The open results database.
    campaign_id : str
        The campaign.
    session_id : int
        The session that computed the seed.
    seed : int
        The seed.
    scores : mapping of str to float
        Its scores.
    elapsed : float
        Its run time [s].
    failure : str or None
        Why it failed (None: it did not).
    db : str
        The database's name, for the message.

    Returns
    -------
    tuple of (dict of str to float, str or None)
        The stored scores and failure reason.
    """
    text = dumps_scores(scores)
    conn.execute("BEGIN IMMEDIATE")
    try:
        conn.execute(
            "INSERT INTO seed_scores "
            "(campaign_id, seed, scores, elapsed_s, finished, session_id) "
            "VALUES (?, ?, ?, ?, ?, ?)",
            (campaign_id, seed, text, elapsed, time.time(), session_id),
        )
        if failure is not None:
            conn.execute(
                "INSERT INTO seed_failures (campaign_id, seed, reason) VALUES (?, ?, ?)",
                (campaign_id, seed, failure),
            )
        conn.execute(
            "INSERT INTO seed_checksums (campaign_id, seed, sha256) VALUES (?, ?, ?)",
            (campaign_id, seed, seed_checksum(campaign_id, seed, text, failure, getattr(conn, "key", b""))),
        )
    except sqlite3.IntegrityError:
        conn.execute("ROLLBACK")
        (other,) = conn.execute(
            "SELECT scores FROM seed_scores WHERE campaign_id = ? AND seed = ?", (campaign_id, seed)
        ).fetchone()
        if other != text:
            raise exits.InternalError(
                f"seed {seed} of campaign {campaign_id} gave different scores in two runs on "
                f"db {db!r}: the scenario or compensator is not deterministic "
                "(it must give the same scores for the same seed)"
            ) from None
        row = conn.execute(
            "SELECT reason FROM seed_failures WHERE campaign_id = ? AND seed = ?",
            (campaign_id, seed),
        ).fetchone()
        failure = row[0] if row else failure
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    else:
        conn.execute("COMMIT")
    return loads_scores(text), failure


# ----------------------------------------------------------------------------- what a campaign read
def campaign_generation(
    conn: sqlite3.Connection, static_id: str, fingerprint: Any
) -> tuple[str, dict[str, Any]]:
    """The campaign id a run of ``static_id`` continues, or a new generation's.

    The campaign of ``static_id`` whose recorded reads still fingerprint the same (``fingerprint``
    maps the stored read names to their fingerprints now), newest first; else a new one: its id
    is ``static_id`` for the first, ``static_id`` hashed with its generation number after.
    Returns (campaign id, the read names recorded for it, empty for a new one).

    Parameters
    ----------
    conn : sqlite3.Connection
        The open results database.
    static_id : str
        The campaign's static id (scenario, compensator, config, identity).
    fingerprint : callable or mapping
        Maps the stored read names to their fingerprints now.

    Returns
    -------
    tuple of (str, dict)
        (campaign id, the read names recorded for it; empty for a new one).
    """
    rows = conn.execute(
        "SELECT campaign_id, generation, names, fingerprint FROM campaign_reads WHERE static_id = ? "
        "ORDER BY generation DESC",
        (static_id,),
    ).fetchall()
    for cid, _gen, names_text, stored in rows:
        try:
            names = json.loads(names_text)
            if fingerprint(names) == json.loads(stored):
                return str(cid), names
        except (ValueError, TypeError):
            continue
    if not rows:
        return static_id, {}
    gen = 1 + max(int(r[1]) for r in rows)
    return hashlib.sha256(f"{static_id}/{gen}".encode()).hexdigest()[:16], {}


def record_reads(
    conn: sqlite3.Connection, campaign_id: str, static_id: str, names: Mapping[str, Any], fingerprint: Mapping[str, str]
) -> None:
    """Store (or replace) what campaign ``campaign_id`` read, with its fingerprints, in one transaction.

    Parameters
    ----------
    conn : sqlite3.Connection
        The open results database.
    campaign_id : str
        The campaign.
    static_id : str
        Its static id.
    names : mapping of str to object
        The read names and what each read.
    fingerprint : mapping of str to str
        Each read name's fingerprint.
    """
    conn.execute("BEGIN IMMEDIATE")
    try:
        row = conn.execute("SELECT generation FROM campaign_reads WHERE campaign_id = ?", (campaign_id,)).fetchone()
        if row is None:
            (gen,) = conn.execute(
                "SELECT COALESCE(MAX(generation) + 1, 0) FROM campaign_reads WHERE static_id = ?", (static_id,)
            ).fetchone()
        else:
            gen = row[0]
        conn.execute(
            "INSERT OR REPLACE INTO campaign_reads VALUES (?, ?, ?, ?, ?)",
            (campaign_id, static_id, int(gen), json.dumps(dict(names), sort_keys=True),
             json.dumps(dict(fingerprint), sort_keys=True)),
        )
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    conn.execute("COMMIT")
