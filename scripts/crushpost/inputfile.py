# SPDX-License-Identifier: GPL-2.0-or-later
"""Reading a user's file with every failure turned into one line that names
the file and says what is wrong (the command line and the report print it
instead of a traceback)."""

import gzip
import re
import warnings
import zlib


class InputFileError(ValueError):
    """A file is missing, empty or not what it should be; the message names it."""


def _why(exc):
    msg = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
    # numpy's advice on a ragged text table is about its own API; a row
    # whose column count changes is a truncated (or hand-edited) file
    msg = re.sub(r"; use `usecols` to select a subset and avoid this error", "", msg)
    if re.search(r"number of columns changed from \d+ to \d+ at row", msg):
        msg += ": truncated while it was being written, or edited by hand?"
    return msg


def reason(exc, path):
    """One line saying why reading ``path`` failed, without the path."""
    msg, p = _why(exc), str(path)
    return msg[len(p):].lstrip(": ") if msg.startswith(p) else msg


def read_checked(path, what, reader, error=InputFileError):
    """``reader()``, with any failure to read ``path`` raised as ``error``
    (an InputFileError class) naming it (``what``: what the file should be,
    e.g. "a LAMMPS text dump"). An InputFileError from the reader passes
    through as it is; so does a message that already starts with the path."""
    try:
        with warnings.catch_warnings():
            # numpy warns on an empty file; the callers say so themselves
            warnings.simplefilter("ignore")
            return reader()
    except InputFileError:
        raise
    except FileNotFoundError:
        raise error("%s: no such file" % path) from None
    except IsADirectoryError:
        raise error("%s: is a folder, not %s" % (path, what)) from None
    except PermissionError:
        raise error("%s: permission denied" % path) from None
    except UnicodeDecodeError as exc:
        raise error("%s: not a text file (byte %d is not UTF-8); expected %s"
                    % (path, exc.start, what)) from None
    except gzip.BadGzipFile:
        raise error("%s: not a gzip file (the name ends in .gz)" % path) from None
    except (EOFError, zlib.error) as exc:
        raise error("%s: truncated or corrupt gzip file (%s)" % (path, exc)) from None
    except (OSError, ValueError, IndexError, KeyError, TypeError) as exc:
        msg, p = _why(exc), str(path)
        at_line = re.match(re.escape(p) + r":(\d+): (.*)", msg)   # "path:9: ..." of a reader
        if at_line:
            raise error("%s: line %s: %s" % (p, at_line.group(1), at_line.group(2))) from None
        if msg.startswith(p):
            raise error(msg) from None
        raise error("%s: not %s (%s)" % (path, what, msg)) from None
