"""How the workbench's features fail.

A user's mistake (a ValueError naming the object, the property and what is allowed; an
OSError for a file; a cancelled preview) is one line in the report view, "Error: <message>",
with no traceback, and the features built on the failed one are marked for recompute, so
none of them stays "up to date" with a result of inputs that no longer hold. Any other
exception is a bug and keeps its traceback.

FreeCAD prints a failing Python feature as "<traceback><str(type)>: <message>" (Base's
PyException). The traceback is Python's own print, which writes nothing while
sys.tracebacklimit is 0: that limit is set only as a user's error leaves a feature, and put
back as the recompute ends (or as the next feature starts, whichever comes first).
"""

import functools
import sys

import FreeCAD

# The exceptions a feature raises for a user's mistake; anything else is a bug.
USER_ERRORS = (ValueError, OSError)

_UNSET = object()
_saved_limit = [_UNSET]  # sys.tracebacklimit as it was before a user's error hid it


class _NamedError(type):
    """FreeCAD puts str() of the exception's type before its message."""

    def __str__(cls):
        return "Error"


class FeatureError(ValueError, metaclass=_NamedError):
    """A user's mistake, worded for the report view: the object, the property, what is
    allowed."""


def restore_tracebacks():
    """Puts sys.tracebacklimit back as it was before a user's error hid the traceback."""
    saved = _saved_limit[0]
    if saved is _UNSET:
        return
    _saved_limit[0] = _UNSET
    if saved is None:
        sys.__dict__.pop("tracebacklimit", None)
    else:
        sys.tracebacklimit = saved


def _hide_traceback():
    if _saved_limit[0] is _UNSET:
        _saved_limit[0] = getattr(sys, "tracebacklimit", None)
    sys.tracebacklimit = 0


def mark_dependents(obj):
    """The features built on obj, marked for recompute: FreeCAD skips them while obj fails,
    and they must not look up to date (nor export) with a result made from before."""
    for dependent in obj.InListRecursive:
        if "Touched" not in dependent.State:
            dependent.touch()


def failure(obj, error):
    """The FeatureError to raise for a user's error in obj's recompute: one line, no
    traceback, dependents marked."""
    mark_dependents(obj)
    _hide_traceback()
    return FeatureError(str(error))


def one_line_errors(execute):
    """Decorates a proxy's execute(self, obj): a user's error leaves as failure(obj, e)."""

    @functools.wraps(execute)
    def wrapped(self, obj):
        restore_tracebacks()
        try:
            return execute(self, obj)
        except USER_ERRORS as e:  # (FeatureError among them)
            raise failure(obj, e) from None

    return wrapped


def failed_inputs(obj):
    """The objects obj is built from that failed their last recompute (FreeCAD has marked
    them invalid): what they show and what they hold is not what their properties say."""
    return [o for o in obj.OutListRecursive if "Invalid" in o.State]


def built_on_failed(obj, then="recompute"):
    """The line saying that obj waits for a failed input, or None when none failed."""
    failed = failed_inputs(obj)
    if not failed:
        return None
    return ("%s is built on %s, which failed its last recompute (%s); fix it and %s"
            % (obj.Label, failed[0].Label, failed[0].getStatusString(), then))


def why_failed(obj):
    """Why obj has no result of its own properties after a recompute, or None: its own
    error, else the input it waits for."""
    if "Invalid" in obj.State:
        return obj.getStatusString()
    return built_on_failed(obj)


class _RecomputeEnd:
    """Puts tracebacks back as each document's recompute ends."""

    def slotRecomputedDocument(self, doc):
        restore_tracebacks()


_recompute_end = _RecomputeEnd()
FreeCAD.addDocumentObserver(_recompute_end)
