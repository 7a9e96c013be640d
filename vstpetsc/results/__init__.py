"""Result files: their layout (:mod:`.layout`), the writer (:mod:`.writer`),
the lazy reader :class:`Result`, the summary of `vstpetsc info` and the
figure of `vstpetsc plot` (the only module that imports matplotlib)."""

from vstpetsc.results.reader import Result

__all__ = ["Result"]
