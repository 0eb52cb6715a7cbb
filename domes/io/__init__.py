"""Files and package data: where the shipped knowledge is, and the file formats read and written.

The rest of the package works on values; this layer turns files into values
and values into files (always written atomically).
"""
