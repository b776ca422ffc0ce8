# Chapter 7: the grid experiment (virtual shaking test or measured records).


def grid_outputs():
    return []
