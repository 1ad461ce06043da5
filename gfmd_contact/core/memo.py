"""Values derived once from a frozen scene (or one of its sections) and handed to every later caller.

A check, a run and its files ask for the same law, model choice and profiles many times; each is a
function of one frozen object, so it is computed on the first request and returned after. Keys are the
object's identity, never its value: a scene's equality runs through a user law's Python callables (which
need not be hashable, and may compare equal without being the same), and 1 == 1.0 == True or −0.0 == 0.0
would let scenes that differ in their bits share a value. An object that cannot be weakly referenced gets
its value built each time.

`per_owner` keeps small values (a law) while their owner lives; `LastOwner` keeps large ones (kernels,
profiles) for the one owner asked for last, so a study's many scenes never hold theirs all at once.
"""

import weakref

_KEPT = {}  # id(owner) → {name: value}; an entry leaves when its owner is collected


def per_owner(owner, name, build):
    """build() on the first request of (owner, name), the same object after, while `owner` lives."""
    values = _KEPT.get(id(owner))
    if values is None:
        try:
            weakref.finalize(owner, _KEPT.pop, id(owner), None)
        except TypeError:  # not weakly referenceable: nothing kept
            return build()
        values = _KEPT[id(owner)] = {}
    if name not in values:
        values[name] = build()
    return values[name]


class LastOwner:
    """Values of the one owner asked for last (by identity), dropped when another is asked for or it dies."""

    def __init__(self):
        self._slot = (None, {})  # (weak reference to the owner, {name: value}), replaced as one tuple

    def get(self, owner, name, build):
        """build() on the first request of (owner, name) since `owner` became the last one, the kept value after."""
        ref, values = self._slot
        if ref is None or ref() is not owner:
            try:
                ref = weakref.ref(owner, self._dropped)
            except TypeError:
                return build()
            values = {}
            self._slot = (ref, values)
        if name not in values:
            values[name] = build()
        return values[name]

    def _dropped(self, ref):
        if self._slot[0] is ref:
            self._slot = (None, {})
