"""Checks of the files a run writes, before anything is written."""

import os


def output_problem(path):
    """Why a result file cannot be written at ``path`` (None if it can)."""
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        return f"folder {folder} does not exist"
    if os.path.isdir(path):
        return f"{path} is a folder"
    if not os.access(folder, os.W_OK) or (os.path.exists(path) and
                                           not os.access(path, os.W_OK)):
        return f"cannot write {path}"
    return None
