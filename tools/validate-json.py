#!/usr/bin/python3
"""Validates ccomp's --json output against its documented schema (docs/schemas/).

    tools/validate-json.py SCHEMA.json OUTPUT.json

OUTPUT may hold one JSON document or JSON Lines (trace, flatten): every line is checked.
Exit 0 when all is valid, 1 with the first error otherwise. Uses Debian's python3-jsonschema.
"""
import json
import sys

import jsonschema

schema = json.load(open(sys.argv[1]))
jsonschema.Draft7Validator.check_schema(schema)
text = open(sys.argv[2]).read()
documents = [json.loads(line) for line in text.splitlines() if line.strip()] if "\n{" in text.strip() else [json.loads(text)]
if not documents:
    sys.exit("no JSON document in " + sys.argv[2])
for n, document in enumerate(documents, 1):
    try:
        jsonschema.validate(document, schema, cls=jsonschema.Draft7Validator)
    except jsonschema.ValidationError as e:
        sys.exit(f"{sys.argv[2]}: document {n}: {e.message} at {list(e.absolute_path)}")
print(f"{len(documents)} document(s) valid against {sys.argv[1]}")
