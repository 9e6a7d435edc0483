"""Many tests of one structure: which mode, and which term of its equation, changed beyond its
uncertainty (:func:`track`)."""
