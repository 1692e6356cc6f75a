"""Untrusted input and unreliable output: the limits every command keeps.

* ``shown(value)``: how a value read from input is echoed (an error line, a table cell): control
  characters escaped, cut to a readable length.
* ``read_text(path, what)``: a file of answers or a baseline, read only when it is a regular file under
  ``MAX_FILE_BYTES``; ``load_toml`` / ``load_json`` parse it after a linear pre-scan that refuses
  nesting and dotted keys deep enough to cost the parsers memory or recursion.
* ``check_output(path, what)`` before the work, ``atomic_write(path, what)`` after it: a file mech
  writes is complete or not written at all; a good old file survives a failed write.
* ``columns()``: ``COLUMNS`` as the tables use it (below 60 read as 60, zero or garbage as unset).
* ``csv_cell(text)``, ``md_text(text)``, ``slugs(names)``: a name from input written into a CSV file a
  spreadsheet opens, into Markdown (or the HTML it renders to), into a file name.

Every refusal is a ``BadInput`` whose message is one line naming the file or the value.
"""

from __future__ import annotations

import contextlib
import itertools
import os
import re
import stat

from mech.core.errors import BadInput

__all__ = ["shown", "shown_path", "escape", "check_apart", "MAX_FILE_BYTES", "MAX_DEPTH", "MAX_KEY_PARTS", "read_text", "load_toml", "load_toml_text",
           "load_json", "check_output", "budget_seconds", "atomic_write", "columns", "normalize_columns", "MIN_COLUMNS",
           "csv_cell", "csv_uncell", "md_text", "slugs"]

SHOWN_CHARS = 80
PATH_CHARS = 240  # a file name is cut later than a value: its end says which file
MAX_FILE_BYTES = 10 * 1024 * 1024
MAX_DEPTH = 32  # nesting of arrays and tables; an answers file needs 3, a baseline 5
MAX_KEY_PARTS = 32  # parts of a dotted TOML key; an answers file needs 2
MIN_COLUMNS = 60

# C0 and C1 controls, DEL, the bidirectional overrides that reorder what a terminal shows, and the
# characters a terminal shows as nothing (zero-width spaces and joiners, the byte-order mark, the soft
# hyphen, line and paragraph separators): echoed as escapes, so what is shown is what was typed
_CONTROL = re.compile("[\x00-\x1f\x7f-\x9f\xad\u180e\u200b-\u200f\u2028-\u202e\u2060-\u2069\ufeff]")


def _escape_one(m: re.Match) -> str:
    c = m.group()
    return {"\n": "\\n", "\t": "\\t", "\r": "\\r"}.get(c) or (f"\\x{ord(c):02x}" if ord(c) < 0x100
                                                              else f"\\u{ord(c):04x}")


def escape(text) -> str:
    """``text`` with every control character written as an escape (``\\x1b``), nothing cut."""
    return _CONTROL.sub(_escape_one, str(text))


def shown_path(path) -> str:
    """A file name from input as it is echoed: escaped, cut at 240 characters."""
    return shown(path, PATH_CHARS)


def shown(value, limit: int = SHOWN_CHARS) -> str:
    """A value from input as it is echoed: control characters escaped, at most ``limit`` characters
    (then "...").  The one function every echo of input goes through."""
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 4 * limit * 3.33:
        # str() of an int past 4300 digits raises: say its size instead
        return f"an integer of {int(value.bit_length() * 0.30103) + 1} digits"
    text = str(value)
    if len(text) > 4 * limit:  # escape no more than is shown
        text = text[:4 * limit]
    text = escape(text)
    return text if len(text) <= limit else text[:limit] + "..."


# -- reading ---------------------------------------------------------------------------------------------

def read_text(path, what: str = "file", limit: int = MAX_FILE_BYTES) -> str:
    """The UTF-8 text of a regular file of at most ``limit`` bytes; BadInput naming the file otherwise.

    Opened without blocking (a FIFO with no writer is refused, not waited on) and read no further than
    the limit (``/dev/zero`` is refused, not read)."""
    name = shown_path(path)
    if str(path) == "":
        raise BadInput(f"{what}: an empty file name")
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except OSError as exc:
        raise BadInput(f"{name}: cannot read the {what}: {exc.strerror or exc}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            kind = "a directory" if stat.S_ISDIR(st.st_mode) else "not a regular file"
            raise BadInput(f"{name}: cannot read the {what}: {kind}")
        if st.st_size > limit:
            raise BadInput(f"{name}: the {what} is {st.st_size} bytes; at most {limit} are read")
        chunks, size = [], 0
        while size <= limit:
            chunk = os.read(fd, min(1 << 20, limit + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        if size > limit:
            raise BadInput(f"{name}: the {what} is over {limit} bytes; at most {limit} are read")
    except OSError as exc:
        raise BadInput(f"{name}: cannot read the {what}: {exc.strerror or exc}") from None
    finally:
        os.close(fd)
    try:
        return b"".join(chunks).decode("utf-8")
    except UnicodeDecodeError as exc:
        raise BadInput(f"{name}: cannot read the {what}: not UTF-8 text (byte {exc.start})") from None


# every alternative matches once started (an unclosed string runs to the end), so the scan is linear
_TOML_STRINGS = re.compile(r'"""[\s\S]*?(?:"""|\Z)|\'\'\'[\s\S]*?(?:\'\'\'|\Z)'
                           r'|"(?:[^"\\\n]|\\.)*(?:"|$)|\'[^\'\n]*(?:\'|$)|#[^\n]*', re.MULTILINE)
_JSON_STRINGS = re.compile(r'"(?:[^"\\]|\\[\s\S])*(?:"|\Z)')
_TABLE_ARRAY_HEADER = re.compile(r"^[ \t]*\[\[", re.MULTILINE)  # ``[[answer]]``, once strings are blanked
_KEY_PART = re.compile(r"\s*(?:[A-Za-z0-9_-]+|\"\")\s*")


def _depth(skeleton: str) -> int:
    """The deepest nesting of ``[``/``{`` in text whose strings are already blanked."""
    opens = skeleton.count("[") + skeleton.count("{")
    if opens <= MAX_DEPTH:
        return opens
    depth = deepest = 0
    for m in re.finditer(r"[\[{]+|[\]}]+", skeleton):
        run = m.group()
        if run[0] in "[{":
            depth += len(run)
            deepest = max(deepest, depth)
        else:
            depth -= len(run)
    return deepest


def _key_parts(skeleton: str) -> int:
    """The most parts of a dotted key (``a.b.c`` has 3) on any line of blanked TOML."""
    worst = 0
    for line in skeleton.splitlines():
        if line.count(".") < MAX_KEY_PARTS - 1:
            continue
        run = 0
        for part in line.split(".")[1:-1]:
            run = run + 1 if _KEY_PART.fullmatch(part) else 0
            worst = max(worst, run + 2)
    return worst


def load_toml(path, what: str = "file") -> dict:
    """A TOML file, read and pre-scanned within the limits, parsed; BadInput naming the file otherwise."""
    return load_toml_text(path, what)[0]


def load_toml_text(path, what: str = "file", max_tables: tuple[int, str] | None = None) -> tuple[dict, str]:
    """``load_toml``'s table and the text it was parsed from (read once).  ``max_tables``: (N, what they
    are): a file with more than N ``[[...]]`` headers is refused before it is parsed (parsing costs some
    nine times the text's size in memory, and each table more again downstream)."""
    import tomllib

    text = read_text(path, what)
    skeleton = _TOML_STRINGS.sub('""', text)
    name = shown_path(path)
    if max_tables is not None:
        most, tables = max_tables
        headers = _TABLE_ARRAY_HEADER.finditer(skeleton)
        if next(itertools.islice(headers, most, None), None) is not None:  # counted no further than N + 1
            raise BadInput(f"{name}: more than {most} {tables}; at most {most} are read (split the file)")
    if _depth(skeleton) > MAX_DEPTH:
        raise BadInput(f"{name}: malformed TOML: nested deeper than {MAX_DEPTH} levels")
    if _key_parts(skeleton) > MAX_KEY_PARTS:
        raise BadInput(f"{name}: malformed TOML: a dotted key of more than {MAX_KEY_PARTS} parts")
    try:
        return tomllib.loads(text), text
    except tomllib.TOMLDecodeError as exc:
        raise BadInput(f"{name}: malformed TOML: {shown(exc, 200)}") from None
    except (ValueError, RecursionError, MemoryError) as exc:  # an integer over Python's 4300 digits
        raise BadInput(f"{name}: malformed TOML: {shown(exc, 200)}") from None


def load_json(path, what: str = "file"):
    """A JSON file, read and pre-scanned within the limits, parsed (NaN and Infinity refused)."""
    import json

    text = read_text(path, what)
    name = shown_path(path)
    if _depth(_JSON_STRINGS.sub('""', text)) > MAX_DEPTH:
        raise BadInput(f"{name}: malformed JSON: nested deeper than {MAX_DEPTH} levels")

    def constant(c):
        raise ValueError(f"{c} is not a finite number")

    try:
        return json.loads(text, parse_constant=constant)
    except json.JSONDecodeError as exc:
        raise BadInput(f"{name}: malformed JSON: {shown(exc, 200)}") from None
    except (ValueError, RecursionError, MemoryError) as exc:
        raise BadInput(f"{name}: malformed JSON: {shown(exc, 200)}") from None


# -- writing ---------------------------------------------------------------------------------------------

def check_output(path, what: str = "output") -> str:
    """Refuse, before any work, an output path mech could not write: empty, a directory, a device or a
    FIFO, in a folder that does not exist or cannot be written.  Returns the path."""
    text = "" if path is None else str(path)
    name = shown_path(text)
    if text.strip() == "":
        raise BadInput(f"{what}: an empty file name; give a file to write")
    try:
        st = os.stat(text)
    except FileNotFoundError:
        st = None
    except OSError as exc:
        raise BadInput(f"{what} {name}: cannot write: {exc.strerror or exc}") from None
    if st is not None and not stat.S_ISREG(st.st_mode):
        kind = "a directory" if stat.S_ISDIR(st.st_mode) else "not a regular file"
        raise BadInput(f"{what} {name}: cannot write: {kind}")
    folder = os.path.dirname(os.path.abspath(text))
    if not os.path.isdir(folder):
        raise BadInput(f"{what} {name}: cannot write: no folder {shown_path(folder)}")
    try:  # the temporary file the write will use must be possible there
        import tempfile

        fd, probe = tempfile.mkstemp(prefix=".mech-", suffix=".probe", dir=folder)
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        raise BadInput(f"{what} {name}: cannot write in {shown_path(folder)}: {exc.strerror or exc}") from None
    return text


def check_apart(outputs, inputs=()) -> None:
    """Refuse, before any work, an output that is the same file as one of ``inputs`` or as another of
    ``outputs`` (each a list of ``(path, what)``; a None path is skipped): an output never overwrites an
    input (``grade hw.toml --junit hw.toml``), nor two outputs each other.  The same file: the same real
    path, or the same device and inode (a hard link)."""
    def ident(path) -> set:
        out = {("path", os.path.realpath(os.path.abspath(str(path))))}
        try:
            st = os.stat(str(path))
            out.add(("inode", st.st_dev, st.st_ino))
        except (OSError, ValueError):
            pass
        return out

    seen = [(ident(p), p, w, "input") for p, w in inputs if p is not None and str(p) != ""]
    for path, what in outputs:
        if path is None or str(path) == "":
            continue
        mine = ident(path)
        for other, opath, owhat, kind in seen:
            if mine & other:
                raise BadInput(f"{what} {shown_path(path)}: the same file as {owhat} {shown_path(opath)}; "
                               f"it would overwrite the {kind}")
        seen.append((mine, path, what, "other output"))


@contextlib.contextmanager
def atomic_write(path, what: str = "output", mode: str = "w", newline: str | None = None):
    """Write ``path`` through a temporary file beside it, flushed to disk, then renamed over it.

    On any failure the temporary file is removed and the old file is left as it was; an OSError (a full
    disk, a quota, a file-size limit) becomes a one-line BadInput naming the file."""
    import tempfile

    text = check_output(path, what)
    _ignore_file_size_signal()
    folder = os.path.dirname(os.path.abspath(text))
    _remove_stale(folder, os.path.basename(text))
    fd, tmp = tempfile.mkstemp(prefix=f"{_tmp_prefix(os.path.basename(text), os.getpid())}", suffix=".tmp",
                               dir=folder)
    try:
        kwargs = {} if "b" in mode else {"encoding": "utf-8", "newline": newline}
        with os.fdopen(fd, mode, **kwargs) as fh:
            yield fh
            fh.flush()
            os.fsync(fh.fileno())
        try:
            os.chmod(tmp, 0o666 & ~_umask())
        except OSError:
            pass
        os.replace(tmp, text)
        tmp = None
    except OSError as exc:
        raise BadInput(f"{what} {shown_path(text)}: cannot write: {exc.strerror or exc}; "
                       "the old file, if any, is left as it was") from None
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):
                os.unlink(tmp)


def _tmp_prefix(base: str, pid: int) -> str:
    """The name a temporary file of ``atomic_write`` starts with: the target's, and the writer's process."""
    return f".{base}.mech{pid}-"


def _remove_stale(folder: str, base: str) -> None:
    """Remove the temporary files of ``base`` left by a writer that was killed (kill -9 leaves no chance to
    clean up): files of mech's own naming whose process no longer runs.  A live writer's file is kept."""
    head = f".{base}.mech"
    try:
        names = [n for n in os.listdir(folder) if n.startswith(head) and n.endswith(".tmp")]
    except OSError:
        return
    for name in names[:1000]:
        pid_text = name[len(head):].split("-", 1)[0]
        if not pid_text.isdigit() or len(pid_text) > 10:
            continue
        pid = int(pid_text)
        if pid == os.getpid() or _alive(pid):
            continue
        with contextlib.suppress(OSError):
            os.unlink(os.path.join(folder, name))


def _alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, OSError):
        return True  # someone else's process, or a number the system cannot take: leave its file alone
    return True


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _ignore_file_size_signal() -> None:
    """Past a file-size limit the kernel sends SIGXFSZ, which kills by default: ignored, the write
    fails with EFBIG instead and the temporary file is cleaned up."""
    import signal
    import threading

    if hasattr(signal, "SIGXFSZ") and threading.current_thread() is threading.main_thread():
        with contextlib.suppress(ValueError, OSError):
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)


# -- the environment -------------------------------------------------------------------------------------

DEFAULT_BUDGET_S = 8.0
MAX_BUDGET_S = 86_400.0  # a day: the largest budget of one solve that still means one


def budget_seconds(environ=None) -> float:
    """A solve's wall-clock budget: ``MECH_BUDGET_S``, or 8 s.  BadInput naming the variable when it is
    not a finite positive number (``nan`` or ``inf`` would switch the budget off)."""
    raw = (os.environ if environ is None else environ).get("MECH_BUDGET_S")
    if raw is None or raw.strip() == "":
        return DEFAULT_BUDGET_S
    try:
        value = float(raw)
    except ValueError:
        value = float("nan")
    if not (0 < value <= MAX_BUDGET_S):
        raise BadInput(f"MECH_BUDGET_S: '{shown(raw, 40)}' is not a number of seconds; allowed (0, {MAX_BUDGET_S:g}]")
    return value


# -- the terminal ----------------------------------------------------------------------------------------

def columns(environ=None) -> int | None:
    """``COLUMNS`` as the tables read it: None when unset, zero, negative or not a number; at least 60."""
    raw = (os.environ if environ is None else environ).get("COLUMNS", "")
    try:
        n = int(str(raw).strip())
    except ValueError:
        return None
    if n <= 0:
        return None
    return max(n, MIN_COLUMNS)


def normalize_columns(environ=None) -> None:
    """Make ``COLUMNS`` in the environment what ``columns()`` reads (rich reads it too): a number of at
    least 60, or unset."""
    env = os.environ if environ is None else environ
    if "COLUMNS" not in env:
        return
    n = columns(env)
    if n is None:
        del env["COLUMNS"]
    elif env["COLUMNS"] != str(n):
        env["COLUMNS"] = str(n)


# -- names written into files other programs open ----------------------------------------------------------

# a cell, or any part of it after a separator a spreadsheet may split on, that starts with one of these
# (after blanks, and after the apostrophes ``csv_cell`` adds) is read as a formula
_CSV_PART = re.compile(r"(^|[,;\t|\r\n])([ \u00a0]*)(?='*[=+\-@\t\r])")
_CSV_MARK = re.compile(r"(^|[,;\t|\r\n])([ \u00a0]*)'(?='*[=+\-@\t\r])")
# a number, perhaps with a unit (letters, digits, ^ * / . and spaces: no call, no DDE, no separator)
_NUMBER = re.compile(r" *[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)? *([A-Za-z/][A-Za-z0-9^*/. ]*)?")


def csv_cell(text) -> str:
    """A text cell a spreadsheet will not run as a formula, whatever separator it splits the file on: every
    part that starts with = + - @ (or a tab, a carriage return), at the cell's start or after a , ; tab |
    or line break, gets an apostrophe before it (read as "text").  A number, with or without its unit
    ("-1.5e-3", "-0.03 m/s"), is left.  ``csv_uncell`` gives the text back."""
    text = str(text)
    if _NUMBER.fullmatch(text):
        return text
    return _CSV_PART.sub(lambda m: m.group(1) + m.group(2) + "'", text)


def csv_uncell(text) -> str:
    """The text ``csv_cell`` was given, from the cell it wrote (a reader of mech's own CSV files)."""
    text = str(text)
    if _NUMBER.fullmatch(text):
        return text
    return _CSV_MARK.sub(lambda m: m.group(1) + m.group(2), text)


_MD_SPECIAL = re.compile(r"([\\`*_{}\[\]()#+!|~\-.])")


def md_text(text) -> str:
    """A name from input as literal text in Markdown and in the HTML it renders to: control characters
    escaped (``\\x1b``, on one line), ``& < >`` as HTML entities (no tag, no comment, no autolink) and
    every Markdown punctuation mark backslash-escaped (no heading, list, emphasis, code, link or image)."""
    text = escape(text).replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")
    return _MD_SPECIAL.sub(r"\\\1", text)


_SLUG_BAD = re.compile(r"[^A-Za-z0-9_-]+")
# names Windows keeps for devices, whatever the extension
_DEVICES = {"con", "prn", "aux", "nul", *(f"com{i}" for i in range(10)), *(f"lpt{i}" for i in range(10))}


def slugs(names, limit: int = 60) -> list[str]:
    """A file name for each of ``names`` (in order): letters, digits, ``_`` and ``-`` only (every other run of
    characters one ``_``), no leading ``-`` or ``_``, at most ``limit`` characters, never a device name, and
    unique even on a file system that ignores case (a clash gets ``-2``, ``-3``, ...)."""
    out, taken = [], set()
    for name in names:
        base = _SLUG_BAD.sub("_", str(name)).strip("_-")[:limit].rstrip("_-") or "student"
        if base.lower() in _DEVICES:
            base += "_"
        slug, k = base, 1
        while slug.lower() in taken:
            k += 1
            slug = f"{base}-{k}"
        taken.add(slug.lower())
        out.append(slug)
    return out
