"""Stage 4 -- the knowledge base: criterion frames, the criterion language, screening."""
