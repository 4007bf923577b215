"""The 1966 machine: the card reader, the port of Appendix C, the 1410 printer.

``cards`` reads a deck; ``program`` is the line-by-line port; ``arithmetic`` the
number models it runs on; ``printer`` edits numbers the 1410 way; ``run`` streams a
deck through the port into a listing; ``ranges`` counts the sheets a range card
prints; ``listing`` reads listings back and compares them field by field.
"""
