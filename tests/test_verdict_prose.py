"""A chapter states a verdict only in the registry's words: glued, never typed.

Where a chapter's prose says how a paper's claim fared, the sentence comes from the registry
(:meth:`xnavlab.reproduce.Result.sentence`, or a verdict glued from a :class:`~xnavlab.reproduce.Check`)
so that the page can never say REPRODUCED where the dashboard says NOT REPRODUCED. This test reads
the markdown of every chapter with its glue roles and code spans taken out and fails on a typed
verdict word of :data:`xnavlab.reproduce.VERDICTS` or :data:`~xnavlab.reproduce.HEADLINES`
(or of the old vocabulary), and on a typed phrase that states an outcome ("is reproduced",
"we reproduce", "confirms the paper", "the claims fail", ...).
"""

import json
import re
from pathlib import Path

import pytest

from xnavlab import reproduce

BOOK = Path(__file__).resolve().parents[1] / "book"
CHAPTERS = sorted(BOOK.glob("[0-9][0-9]_*.ipynb"))

_ROLE = re.compile(r"\{glue(?::\w+)?\}`[^`]*`|\{eval\}`[^`]*`")
_CODE = re.compile(r"``[^`]*``|`[^`]*`")
_MATH = re.compile(r"\$\$.*?\$\$|\$[^$]*\$", re.S)
#: the verdict words, typed in capitals (any of the registry's, and the retired ones)
_WORDS = sorted({*reproduce.VERDICTS, *reproduce.HEADLINES, "PASS", "FAIL", "NOT CLAIMED"},
                key=len, reverse=True)
_TYPED_WORD = re.compile(r"\b(?:" + "|".join(re.escape(w) for w in _WORDS) + r")\b")
#: phrases that state an outcome in the chapter's own words
_PHRASES = re.compile(
    r"\b(?:(?:is|are|was|were|not|partly|fully|all)\s+reproduced"
    r"|we\s+(?:do\s+not\s+)?reproduce\b"
    r"|reproduces\s+the\s+paper"
    r"|(?:confirms?|confirmed|refutes?|refuted)\s+the\s+paper"
    r"|the\s+paper'?s\s+claims?\s+(?:holds?|fails?|then\s+fails?)"
    r"|claims?\s+(?:then\s+)?fail\b"
    r"|as\s+the\s+paper\s+(?:claims|reports)\s+it\s+holds)",
    re.I)


def _prose(path):
    nb = json.loads(path.read_text(encoding="utf-8"))
    for i, cell in enumerate(nb["cells"]):
        if cell["cell_type"] != "markdown":
            continue
        text = "".join(cell["source"])
        yield i, _MATH.sub(" ", _CODE.sub(" ", _ROLE.sub(" ", text)))


@pytest.mark.parametrize("path", CHAPTERS, ids=[p.stem for p in CHAPTERS])
def test_a_chapter_types_no_verdict(path):
    found = []
    for i, text in _prose(path):
        for m in _TYPED_WORD.finditer(text):
            found.append(f"cell {i}: typed verdict {m.group()!r}")
        for m in _PHRASES.finditer(text):
            found.append(f"cell {i}: typed outcome {m.group()!r}")
    assert not found, (f"{path.name}: glue the registry's sentence (Result.sentence) or verdict "
                       "instead:\n" + "\n".join(found))


def test_the_phrases_and_words_are_caught_and_glue_is_not():
    typed = "The ranking is not reproduced; the paper's claims then fail. Verdict: REPRODUCED."
    assert len(_TYPED_WORD.findall(typed)) == 1 and len(_PHRASES.findall(typed)) == 2
    glued = "Our verdict: {glue:text}`ch10_ranking_verdict`; see `reproduce.REPRODUCED`."
    assert not _TYPED_WORD.search(_CODE.sub(" ", _ROLE.sub(" ", glued)))
