"""The command line: ``clearance COMMAND``, one module per sub-command.

``main`` builds the parser and maps errors to exit codes (0 clear, 1 not clear, 2 bad input,
3 internal or simulator error); ``options`` holds the options the commands share; each of
``report``, ``vehicles``, ``curves``, ``simulate``, ``compare`` and ``check`` parses its
options and calls library functions.
"""
