"""Input errors of the core: every message names the key, the value and what is allowed."""


class SceneError(ValueError):
    """Invalid scene input: the message names the key, the value and what is allowed."""
