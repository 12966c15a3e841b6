"""Stub: the Job an operation belongs to (none here: the post's defaults apply)."""


def findParentJob(obj):
    return None
