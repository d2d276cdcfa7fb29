// WIP: being written in this session.
