"""Runs a "# %%"-celled Python script and writes it as Markdown: each cell's code, then its output.

Usage: python3 examples/python/render_markdown.py SCRIPT [--update DOC]
Without --update, prints the Markdown. With --update, replaces the text between the lines
"<!-- walkthrough:begin -->" and "<!-- walkthrough:end -->" of DOC (docs/PYTHON.md).
The test python/tests/test_walkthrough.py checks that DOC's cells are the script's and that its
outputs have the same shape (numbers aside).
"""
import contextlib
import io
import sys

BEGIN, END = "<!-- walkthrough:begin -->", "<!-- walkthrough:end -->"


def cells(path):
    """[(title, code)] of the script: the text before the first "# %%" is its header, not a cell."""
    out = []
    for chunk in open(path).read().split("\n# %%")[1:]:
        title, _, code = chunk.partition("\n")
        out.append((title.strip(), code.strip("\n")))
    return out


def render(path):
    namespace = {"__name__": "__walkthrough__"}
    md = []
    for title, code in cells(path):
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            exec(compile(code, f"{path}:{title}", "exec"), namespace)
        md.append(f"**{title}**\n\n```python\n{code}\n```\n")
        if buf.getvalue().strip():
            md.append("```text\n" + buf.getvalue().rstrip("\n") + "\n```\n")
    return "\n".join(md)


def section(doc_text):
    a, b = doc_text.index(BEGIN), doc_text.index(END)
    return doc_text[a + len(BEGIN):b].strip("\n")


def main(argv):
    if len(argv) not in (2, 4) or (len(argv) == 4 and argv[2] != "--update"):
        sys.exit(__doc__)
    md = render(argv[1])
    if len(argv) == 2:
        print(md)
        return
    doc = open(argv[3]).read()
    a, b = doc.index(BEGIN) + len(BEGIN), doc.index(END)
    with open(argv[3], "w") as f:
        f.write(doc[:a] + "\n" + md + "\n" + doc[b:])


if __name__ == "__main__":
    main(sys.argv)
