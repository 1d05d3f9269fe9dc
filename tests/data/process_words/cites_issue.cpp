// Fixture of tests/check_words.cmake: a comment citing issue 12, which the check must refuse.
