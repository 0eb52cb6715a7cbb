"""DOMES Studio: the design dialogue, a mechanism editor, synthesis panels and the knowledge base in the browser.

``domes studio`` serves a local web application (:func:`~domes.studio.app.make_app`) on the loopback address.
Every page asset is shipped in ``static/``; the server's routes are thin wrappers over the library functions
the command line calls (:mod:`domes.studio.mechanism`, :mod:`domes.studio.synthesis`,
:mod:`domes.studio.knowledge`, :mod:`domes.studio.dialogue`), and :mod:`domes.studio.security` keeps requests
on the loopback address, inside the user's data folder and small.
"""
