"""The cam at its speed (THEORY §I, §J, §K): the elastic follower train's exact steady state
(:mod:`~camfab.speed.elastic`) and what it says (:mod:`~camfab.speed.vibration`), Hertz contact
(:mod:`~camfab.speed.hertz`), where the follower bears on the cam and the roller's life
(:mod:`~camfab.speed.contact`), all of it on one analysis with its checks
(:mod:`~camfab.speed.model`), and the contact stress and the roller's life as limits of the
sizing (:mod:`~camfab.speed.stress_sizing`, :mod:`~camfab.speed.life_sizing`).

It stands above :mod:`camfab.analysis` (the findings, the dynamics, the sizing's grids, the
``Analysis`` record it adds to); the follower train's lumped model it drives is the design's
(:mod:`camfab.design.train`).
"""
