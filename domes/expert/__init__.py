"""The design expert: production rules (experta), case-based reasoning and the design dialogue.

- :mod:`domes.expert.engine` and :mod:`domes.expert.facts` -- the rules and the facts they act on;
- :mod:`domes.expert.reasoner` -- same, similar or different from a solved problem;
- :mod:`domes.expert.world` -- what the rules act on: the case base, the design run, the designer;
- :mod:`domes.expert.run` -- the design run: numbers, chains, labelled candidates, screening;
- :mod:`domes.expert.dialogue` -- the question-answer session;
- :mod:`domes.expert.replay` -- recorded cases replayed as regression tests.
"""
