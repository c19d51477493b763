"""Mechanism definitions: one file per mechanism, each defining ``build() -> Mechanism``.

The generator finds them by listing this folder (``parakin.generator.build.discover``); a new
file here is a new mechanism, its name the file's stem. Nothing else needs editing.
"""
