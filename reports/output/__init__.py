"""Output safety: nothing a user had is lost or half-written.

- ``atomic``: a file is the previous version or the complete new one.
- ``output_dir``: an output folder replaced as a whole, or not at all.
- ``file_names``: file names made from ids.
"""
