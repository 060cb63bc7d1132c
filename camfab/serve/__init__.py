"""``camfab serve``: the studio, a live page of one design in the browser.

:mod:`~camfab.serve.studio` holds the state (the design file, the edits not saved, the last
design that loaded and its analysis), :mod:`~camfab.serve.yamledit` edits the YAML text in
place, :mod:`~camfab.serve.scene` gives the 3-D view its part and follower,
:mod:`~camfab.serve.watch` follows the files on disk (watchfiles),
:mod:`~camfab.serve.app` is the web application (Starlette) and :mod:`~camfab.serve.run` the
server (uvicorn) the command line starts. The libraries are the optional extra
``camfab[serve]``; three.js is vendored in ``static/three`` (its README says which version).
"""
