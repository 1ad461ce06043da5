"""Input errors of the core: every message names the key, the value and what is allowed."""


class SceneError(ValueError):
    """Invalid scene input: the message names the key, the value and what is allowed."""


def first_line(exc, limit=120):
    """First line of an exception's message, at most `limit` characters (for an error that quotes its cause)."""
    text = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
    return text if len(text) <= limit else text[:limit] + " …"
