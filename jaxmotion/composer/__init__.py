"""The composer: a web page where a person draws a path on the ground, lays actions along it and watches Neural
Marionette perform them (the paper's interactive system, §6 and the supplement's §5, as a page instead of a Blender
add-on).

    python -m jaxmotion.composer RUN [--port 8000] [--host 127.0.0.1]

:mod:`jaxmotion.composer.app` holds what the page asks for as plain functions over a loaded generator (the program a
request describes, the chain with progress, the downloads); :mod:`jaxmotion.composer.server` serves it with the
standard library's threaded HTTP server (no web framework: one user on localhost needs none, and the package gains no
dependency); ``static/`` is the page, plain JavaScript with no library (the 3D view is drawn on a 2D canvas).
``docs/composer.md`` shows it.
"""
