"""``jupyter-book build``, with Sphinx reading and writing the pages on several processes.

``make book`` renders the book with Jupyter Book 1's own build (``_config.yml`` and
``_toc.yml``, the same options as ``jupyter-book build . -W -n --keep-going``). Its command
line has no option for Sphinx's parallel build, which its Python function
(``jupyter_book.sphinx.build_sphinx``) takes as ``jobs``: this script gives it ``--jobs``
and then runs the command line unchanged. Every extension of the book declares itself safe
for parallel reading and writing, or Sphinx says it is not (a warning, which ``-W`` makes an
error), so a build that passes here is the serial build's.

Measured on 2 cores (the chapters already executed): see the Makefile's ``book`` target.

Usage: ``python tools/book_build.py [--jobs N] [jupyter-book build options] PATH``.
"""

import argparse
import functools
import os
import sys


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0], add_help=False)
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    args, rest = parser.parse_known_args(argv)
    if args.jobs < 1:
        print(f"book_build: --jobs must be at least 1, got {args.jobs}", file=sys.stderr)
        return 2
    from jupyter_book import sphinx as jb_sphinx
    from jupyter_book.cli.main import main as jupyter_book_cli

    # jupyter-book's build command imports build_sphinx from this module when it runs
    jb_sphinx.build_sphinx = functools.partial(jb_sphinx.build_sphinx, jobs=args.jobs)
    return jupyter_book_cli(["build", *rest], standalone_mode=True)


if __name__ == "__main__":
    sys.exit(main())
