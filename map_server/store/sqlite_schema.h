#ifndef FLEETMAP_MAP_SERVER_STORE_SQLITE_SCHEMA_H_
#define FLEETMAP_MAP_SERVER_STORE_SQLITE_SCHEMA_H_

#include <string>

struct sqlite3;

namespace fleetmap {

// The schema version this build writes. Bump it by appending a migration in sqlite_schema.cc.
constexpr int kSqliteSchemaVersion = 3;

// Reads the database's schema version (0 for an empty database); -1 with `error` when the file
// is not a fleetmap database.
int ReadSchemaVersion(sqlite3* db, std::string* error);

// Brings the database up to kSqliteSchemaVersion, one migration per transaction. Refuses a
// database written by a newer server (its schema is unknown to us) with an actionable message.
bool MigrateSchema(sqlite3* db, std::string* error);

}  // namespace fleetmap

#endif  // FLEETMAP_MAP_SERVER_STORE_SQLITE_SCHEMA_H_
