"""MkDocs hook (mkdocs.yml, ``hooks:``): the images the pages show from outside docs/ are published with the site, and
inline code of several words wraps only at its spaces.

A page shows a figure the validation scripts write where they write it, ``![...](../validation/output/x/y.png)``, a
link that also works on the repository's own file view. MkDocs knows only the files under docs/, so this hook adds
each such image to the site's files under ``repository/<its path in the repository>``; MkDocs then checks the link
and rewrites it to that copy like any other. Links to other files outside docs/ are not links: the pages name such a
file by its path from the repository root, in code.

Inline code of several words (a command, ``--set KEY=VALUE``) may wrap, but only at its spaces: each word is put in a
``<span>`` that docs/stylesheets/layout.css keeps on one line, so a key name or a path never breaks inside itself while
a long command still fits the text column.
"""

from __future__ import annotations

import posixpath
import re
from pathlib import Path

from mkdocs.structure.files import File, Files, InclusionLevel

IMAGES = (".png", ".gif", ".jpg", ".svg")
INLINE_CODE = re.compile(r"(?<!<pre>)(?<!</span>)<code>([^<]*?\s[^<]*)</code>")   # not a code block's <code>
LINK = re.compile(r"\]\(([^)\s]+)\)")


def on_files(files: Files, config) -> Files:
    docs = Path(config["docs_dir"]).resolve()
    root = docs.parent
    wanted = set()
    for page in files.documentation_pages():
        for target in LINK.findall(Path(page.abs_src_path).read_text(encoding="utf-8")):
            uri = posixpath.normpath(posixpath.join(posixpath.dirname(page.src_uri), target))
            if uri.startswith("../") and uri.lower().endswith(IMAGES):
                wanted.add(uri)
    for uri in sorted(wanted):
        path = (docs / uri).resolve()
        if root in path.parents and path.is_file():
            files.append(File(uri, str(docs), config["site_dir"], config["use_directory_urls"],
                              dest_uri="repository/" + path.relative_to(root).as_posix(),
                              inclusion=InclusionLevel.INCLUDED))   # a path from ../ is no hidden file
    return files


def on_page_content(html: str, page, config, files) -> str:
    return INLINE_CODE.sub(_words, html)


def _words(match: re.Match) -> str:
    words = "".join(f"<span>{word}</span>" if word.strip() else word for word in re.split(r"(\s+)", match[1]))
    return f'<code class="words">{words}</code>'
